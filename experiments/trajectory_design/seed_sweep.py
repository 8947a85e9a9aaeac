#!/usr/bin/env python3
"""Many seeds of one trajectory, calibrated with gyrosid's best noisy calibration (rbf_noisy.yaml) and scored on the
short and medium flights (optionally long): the end-position error vectors and the fits' evidence figures per seed.

    seed_sweep.py GYROSID NAME TRAJECTORY --seeds 11-50 [--long] [--sensor S] [--calibration C] [--work DIR] --out results/seed_sweep_NAME.json

Each seed costs a few seconds (62-min dual scan: simulate 0.01 s, calibrate 2 s, cof short/medium 0.3 s, long
1.4 s). Cached per seed under --work (default /tmp/gyrosid-seed-sweep), so a stopped run resumes. The figures
per seed: criterion of fit and NED error vector per flight, the network's effective parameters, widths, alpha and
the estimated white noise (model.json summary). Same simulate/calibrate/cof commands as run.py's `score`.
"""
import argparse
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))


def seeds_of(text):
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    return out


def run(argv, product):
    if not os.path.exists(product):
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    return product


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("gyrosid")
    ap.add_argument("name")
    ap.add_argument("trajectory")
    ap.add_argument("--seeds", default="1-10")
    ap.add_argument("--long", action="store_true")
    ap.add_argument("--sensor", default="builtin:sensors/open_loop_fog.yaml", help="sensor config (e.g. other_fog.yaml, the second sensor)")
    ap.add_argument("--calibration", default="builtin:calibration/rbf_noisy.yaml", help="calibration config (e.g. a design's calibration.yaml)")
    ap.add_argument("--work", default="/tmp/gyrosid-seed-sweep")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    g = [a.gyrosid, "--quiet"]
    flights = {"short": [], "medium": []}
    if a.long:
        flights["long"] = ["--rate-hz", "10"]
    rows = {}
    for s in seeds_of(a.seeds):
        d = os.path.join(a.work, a.name, "s%d" % s)
        os.makedirs(d, exist_ok=True)
        model = os.path.join(d, "model.json")
        if not os.path.exists(model):
            rec = run(g + ["simulate", "--sensor", a.sensor, "--trajectory", a.trajectory, "--seed", str(s), "--out", os.path.join(d, "rec.csv")],
                      os.path.join(d, "rec.csv"))
            run(g + ["calibrate", "--recording", rec, "--config", a.calibration, "--out", model], model)
            os.remove(rec)  # 1.3 MB each; the model is what is kept
        row = {}
        for f, extra in flights.items():
            c = run(g + ["cof", "--model", model, "--sensor", a.sensor, "--trajectory", f] + extra + ["--out", os.path.join(d, f)],
                    os.path.join(d, f, "cof.json"))
            j = json.load(open(c))
            row[f] = {"cof_m": j.get("error_after_1h_m", j["end_error_m"]), "error_ned_m": j["error_ned_m"]}
        det = json.load(open(model))["summary"]["details"]
        row["fit"] = {k: det.get(k) for k in ("effective_parameters", "width", "alpha", "beta", "noise_sigma_radps", "noise_choice")}
        rows[s] = row
    json.dump(rows, open(a.out, "w"), indent=1)


if __name__ == "__main__":
    main()
