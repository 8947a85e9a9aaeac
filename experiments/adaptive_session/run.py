#!/usr/bin/env python3
"""Does an adaptive session (pilot, posterior, redesign) transfer to sensors it was not given (issue 32, item 2)?

    /usr/bin/python3 experiments/adaptive_session/run.py [--gyrosid build/gyrosid] [--seeds 1-3] [--model hybrid]

For each test sensor and seed: `gyrosid session --prior builtin:priors/open_loop_fog_type.yaml --truth S
--budget-min 60 --model M --seed s` (15-min pilot designed for the 8-member prior, the tempered posterior, a 45-min redesign
that continues the pilot, the final calibration with the design's calibration.yaml, model M), then `gyrosid cof` of the
final model on the three flights. The test sensors are design_under_prior's: other_fog.yaml (written
independently of the prior) and four held-out units drawn by that script's numpy implementation of the prior's
laws (seeds 101-104). The baselines - the 62-min dual scan and the 60-min design for the prior (same calibration),
and the 8-h soak (classical model) - are the same seeds of design_under_prior's sweeps (run that first; its cache
is --baseline-work, run with the same --model). Writes results/summary_<model>.json and .md.
"""
import argparse
import importlib.util
import json
import os
import subprocess
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
FLIGHTS = {"short": [], "medium": [], "long": ["--rate-hz", "10"]}
BASELINES = {"dual scan": "dualscan", "design for the prior": "designprior", "8-h soak, classical": "8hsoakclassical"}


def load_design_under_prior():
    spec = importlib.util.spec_from_file_location("design_under_prior", os.path.join(ROOT, "experiments", "design_under_prior", "run.py"))
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


def seeds_of(text):
    a, _, b = text.partition("-")
    return list(range(int(a), int(b or a) + 1))


def session(g, sensor, seed, d, model):
    if not os.path.exists(os.path.join(d, "session.json")) or json.load(open(os.path.join(d, "session.json"))).get("status") != "complete":
        start = time.time()
        subprocess.run([g, "--quiet", "session", "--prior", "builtin:priors/open_loop_fog_type.yaml", "--truth", sensor, "--budget-min", "60",
                        "--model", model, "--seed", str(seed), "--out", d] + (["--resume"] if os.path.exists(d) else []), check=True, stdout=subprocess.DEVNULL)
        json.dump({"s": time.time() - start}, open(os.path.join(d, "time.json"), "w"))
    row = {}
    for f, extra in FLIGHTS.items():
        out = os.path.join(d, "cof_" + f)
        if not os.path.exists(os.path.join(out, "cof.json")):
            subprocess.run([g, "--quiet", "cof", "--model", os.path.join(d, "model.json"), "--sensor", sensor, "--trajectory", f] + extra + ["--out", out],
                           check=True, stdout=subprocess.DEVNULL)
        j = json.load(open(os.path.join(out, "cof.json")))
        row[f] = j.get("error_after_1h_m", j["end_error_m"])
    s = json.load(open(os.path.join(d, "session.json")))
    return {"achieved_m": row, "predicted": s["final"]["predicted"], "time_s": json.load(open(os.path.join(d, "time.json")))["s"],
            "posterior": [{m["name"]: round(m["weight"], 4) for m in seg["posterior"]["members"] if m["weight"] > 1e-3} for seg in s["segments"]],
            "learning_rate": [seg["posterior"]["learning_rate"] for seg in s["segments"]]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gyrosid", default=os.path.join(ROOT, "build", "gyrosid"))
    ap.add_argument("--seeds", default="1-3")
    ap.add_argument("--work", default="/tmp/gyrosid-adaptive-session")
    ap.add_argument("--baseline-work", default="/tmp/gyrosid-design-under-prior")
    ap.add_argument("--baseline-seeds", default="1-8", help="the seeds design_under_prior's sweeps ran (their files' suffix)")
    ap.add_argument("--model", default="hybrid", help="the session's model (gyrosid session --model; auto is the hybrid here); results go to results/summary_<model>.*")
    a = ap.parse_args()
    dup = load_design_under_prior()
    os.makedirs(a.work, exist_ok=True)
    sensors = {"other_fog (independent)": os.path.join(ROOT, "experiments", "trajectory_design", "other_fog.yaml")}
    for base, seed in (("open_loop_fog.yaml", 101), ("open_loop_fog.yaml", 102), ("open_loop_fog_drift.yaml", 103), ("open_loop_fog_drift.yaml", 104)):
        sensors["type unit %d (%s)" % (seed, base.split(".")[0])] = dup.held_out_member(base, seed, os.path.join(a.work, "unit_%d.yaml" % seed))
    summary = {"seeds": a.seeds, "model": a.model, "sensors": {}}
    for sname, spath in sensors.items():
        tag = os.path.splitext(os.path.basename(spath))[0]
        rows = {}
        for seed in seeds_of(a.seeds):
            r = session(a.gyrosid, spath, seed, os.path.join(a.work, "%s_%s_s%d" % (a.model, tag, seed)), a.model)
            for bname, key in BASELINES.items():
                sweep = json.load(open(os.path.join(a.baseline_work, "sweep_%s_%s_%s.json" % (tag, key, a.baseline_seeds))))
                r[bname] = {f: sweep[str(seed)][f]["cof_m"] for f in FLIGHTS}
            rows[seed] = r
            print(sname, seed, json.dumps({k: v for k, v in r.items() if k != "predicted"}))
        summary["sensors"][sname] = rows
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    json.dump(summary, open(os.path.join(HERE, "results", "summary_%s.json" % a.model), "w"), indent=1)
    lines = table(summary) + [""] + aggregate(summary)
    open(os.path.join(HERE, "results", "summary_%s.md" % a.model), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


def table(summary):
    lines = ["| test sensor | seed | flight | session | dual scan | design for the prior | 8-h soak | session / dual | session / prior design | "
             "session / soak | predicted (mean [min, max]) / achieved |", "|---" * 11 + "|"]
    for sname, rows in summary["sensors"].items():
        for seed, r in rows.items():
            for f in FLIGHTS:
                s, p = r["achieved_m"][f], r["predicted"][f]
                lines.append("| %s | %s | %s | %.3g | %.3g | %.3g | %.3g | %.2fx | %.2fx | %.2fx | %.2f [%.2f, %.2f] |" % (
                    sname, seed, f, s, r["dual scan"][f], r["design for the prior"][f], r["8-h soak, classical"][f], r["dual scan"][f] / s,
                    r["design for the prior"][f] / s, r["8-h soak, classical"][f] / s, p["cof_mean_m"] / s, p["cof_min_m"] / s, p["cof_max_m"] / s))
    return lines


def aggregate(summary):
    lines = ["| trajectory | geometric mean gain of the session | flights the session loses | its worst gain |", "|---|---|---|---|"]
    for b in BASELINES:
        g = [r[b][f] / r["achieved_m"][f] for rows in summary["sensors"].values() for r in rows.values() for f in FLIGHTS]
        lines.append("| %s | %.2fx | %d of %d | %.2fx |" % (b, float(np.exp(np.mean(np.log(g)))), sum(x < 1 for x in g), len(g), min(g)))
    lines += ["", "Per flight, the geometric mean over seeds of the session's gain, on each test sensor (issue 32's targets: >= 1.2x short, "
              ">= 1.5x medium and long over the dual scan; > 1x over the soak):", "",
              "| test sensor | " + " | ".join("%s: / dual, / prior design, / soak" % f for f in FLIGHTS) + " |", "|---" * (1 + len(FLIGHTS)) + "|"]
    for sname, rows in summary["sensors"].items():
        cells = []
        for f in FLIGHTS:
            gm = [float(np.exp(np.mean([np.log(r[b][f] / r["achieved_m"][f]) for r in rows.values()]))) for b in BASELINES]
            cells.append("%.2fx, %.2fx, %.2fx" % tuple(gm))
        lines.append("| %s | %s |" % (sname, " | ".join(cells)))
    within = [0.667 <= r["predicted"][f]["cof_mean_m"] / r["achieved_m"][f] <= 1.5 for rows in summary["sensors"].values() for r in rows.values() for f in FLIGHTS]
    covered = [r["predicted"][f]["cof_min_m"] <= r["achieved_m"][f] <= r["predicted"][f]["cof_max_m"]
               for rows in summary["sensors"].values() for r in rows.values() for f in FLIGHTS]
    times = [r["time_s"] for rows in summary["sensors"].values() for r in rows.values()]
    lines += ["", "Predicted mean within 1.5x of achieved: %d of %d; the prior band covers the achieved value: %d of %d." % (
        sum(within), len(within), sum(covered), len(covered)),
              "Session wall time (design, simulate, calibrate, redesign, final calibration): median %.0f s, max %.0f s." % (
                  float(np.median(times)), max(times))]
    return lines


if __name__ == "__main__":
    main()
