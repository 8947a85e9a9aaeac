#!/usr/bin/env python3
"""Predicted against achieved criterion of fit, split into the model class's part and the noise's part.

    predictor_check.py GYROSID NAME=TRAJECTORY.yaml[,CALIBRATION.yaml] ... --seeds 1,2,3 [--tag reference]

For each trajectory: `design --evaluate` (cof_m, cof_bias_m |m|, cof_noise_m sqrt(tr S Sigma S')); a noise-free
recording calibrated with the design's calibration (the hybrid given the sensor's noise: the calibration's own
model-class error m, achieved); and the noisy recordings of run.py's cache (seeds). Per flight the noisy
end-position error vectors (short, medium: NED at the end) give the achieved mean vector and the spread about
it (the noise's part, achieved): sqrt(mean |dp_s - mean|^2 * n/(n-1)). Writes results/predictor_check.json.
"""
import argparse
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import yaml  # noqa: E402
import run  # noqa: E402
from gyrosid_experiments import load_json  # noqa: E402

FLIGHTS = ["short", "medium", "long"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("gyrosid")
    ap.add_argument("trajectories", nargs="+")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--tag", default="reference")
    ap.add_argument("--calibration", default="best", help="best (rbf_noisy.yaml) or given: the noisy recordings are fitted with the "
                    "CALIBRATION.yaml given beside each trajectory (the design's calibration.yaml: the hybrid given the sensor's noise)")
    ap.add_argument("--sensor", default=None, help="sensor config (default: config.yaml's; e.g. other_fog.yaml, the second sensor)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "predictor_check.json"))
    ap.add_argument("--evaluation", default="evaluate", help="the cache directory of this binary's `design --evaluate` (check/NAME)")
    ap.add_argument("--set", action="append", default=[], help="design option for the evaluation, e.g. model.network=dictionary")
    a = ap.parse_args()
    cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))
    st = run.Study(argparse.Namespace(gyrosid=a.gyrosid, out=os.path.join(HERE, "results"), force=False, max_minutes=600), cfg)
    sensor = st.sensor_path(a.sensor) if a.sensor else cfg["sensor"]
    items = []
    for spec in a.trajectories:
        name, rest = spec.split("=", 1)
        path, _, cal = rest.partition(",")
        items.append((name, path, cal))
    given = next((c for _, _, c in items if c), None)
    d = st.run.path(a.tag, "check", a.evaluation, "x")[:-2]
    sets = [x for kv in a.set for x in ("--set", kv)]
    st.gyrosid(["design", "--evaluate"] + [p for _, p, _ in items] + ["--model", "hybrid", "--envelope", cfg["design"]["envelope"],
                                                                    "--sensor", sensor] + sets + ["--out", d], os.path.join(d, "evaluation.json"))
    ev = load_json(os.path.join(d, "evaluation.json"))["trajectories"]
    out = {}
    for name, path, own_cal in items:
        row = {"predicted": {f: ev[path]["flights"][f] for f in FLIGHTS}, "network": ev[path].get("network")}
        # the model class's part, achieved: a noise-free recording, the calibration given the sensor's noise
        if given:
            rec = st.run.path(a.tag, "check", "%s_noise_free.csv" % name)
            st.gyrosid(["simulate", "--sensor", sensor, "--trajectory", path, "--seed", 1, "--noise-free", "--out", rec], rec)
            model = st.run.path(a.tag, "check", "%s_noise_free_model.json" % name)
            st.gyrosid(["calibrate", "--recording", rec, "--config", given, "--out", model], model)
            nf = {}
            for flight, extra in cfg["flights"].items():
                cd = st.run.path(a.tag, "check", "%s_noise_free_%s" % (name, flight), "x")[:-2]
                st.gyrosid(["cof", "--model", model, "--sensor", sensor, "--trajectory", flight] + extra + ["--out", cd], os.path.join(cd, "cof.json"))
                j = load_json(os.path.join(cd, "cof.json"))
                nf[flight] = j.get("error_after_1h_m", j["end_error_m"])
            row["noise_free_m"] = nf
        seeds = [int(s) for s in a.seeds.split(",")]
        if a.calibration == "given" and not own_cal:
            sys.exit("--calibration given: give each trajectory as NAME=TRAJECTORY.yaml,CALIBRATION.yaml")
        label, cal = ("best", cfg["calibrations"]["best"]) if a.calibration == "best" else ("given_%s" % name, ["--config", own_cal])
        per = {f: [] for f in FLIGHTS}
        vec = {f: [] for f in FLIGHTS}
        for s in seeds:
            r = st.score(a.tag, sensor, name, path, s, label, cal)
            for f in FLIGHTS:
                per[f].append(r[f])
                j = load_json(os.path.join(st.run.out, a.tag, "cof", "%s_s%d_%s_%s" % (name, s, label, f), "cof.json"))
                vec[f].append(j["error_ned_m"])
        ach = {}
        for f in FLIGHTS:
            n = len(seeds)
            mean = [sum(v[i] for v in vec[f]) / n for i in range(3)]
            spread = math.sqrt(sum(sum((v[i] - mean[i]) ** 2 for i in range(3)) for v in vec[f]) / max(1, n - 1))
            ach[f] = {"mean_m": sum(per[f]) / n, "per_seed_m": per[f], "mean_vector_norm_m": math.sqrt(sum(m * m for m in mean)),
                      "spread_m": spread, "vectors": vec[f]}
        row["achieved"] = ach
        out[name] = row
        sys.stderr.write("%s\n" % name)
        for f in FLIGHTS:
            p = row["predicted"][f]
            sys.stderr.write("  %-6s achieved %.3g (|mean| %.3g, spread %.3g%s) predicted %.3g (bias %.3g, noise %.3g, posterior %.3g)\n" % (
                f, ach[f]["mean_m"], ach[f]["mean_vector_norm_m"], ach[f]["spread_m"],
                (", noise-free %.3g" % row["noise_free_m"][f]) if given else "", p["cof_m"], p["cof_bias_m"], p["cof_noise_m"], p["cof_posterior_m"]))
    within = [(n, f, r["predicted"][f]["cof_m"] / r["achieved"][f]["mean_m"]) for n, r in out.items() for f in FLIGHTS]
    sys.stderr.write("predicted / achieved mean: %s; within 1.5x: %d of %d\n" % (
        ", ".join("%s %s %.2f" % w for w in within), sum(1 for w in within if 1 / 1.5 <= w[2] <= 1.5), len(within)))
    json.dump(out, open(a.out, "w"), indent=1)


if __name__ == "__main__":
    main()
