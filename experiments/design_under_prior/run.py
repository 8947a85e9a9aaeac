#!/usr/bin/env python3
"""Does a design for a prior over sensors transfer to sensors it was not given (issue 32, item 1)?

    /usr/bin/python3 experiments/design_under_prior/run.py [--gyrosid build/gyrosid] [--seeds 1-3]

Two 60-min designs (default model rbf, criterion cof, nlopt, seed 1): one for the reference sensor alone
(--sensor), one for the open-loop FOG type prior (--prior builtin:priors/open_loop_fog_type.yaml, 8 members).
Both, the 62-min dual scan (same calibration) and the 8-h soak (classical model) are simulated on test sensors
the designs were not given, calibrated, and scored by `gyrosid cof` on the three flights (seed_sweep.py of
experiments/trajectory_design):
  * other_fog.yaml - written independently of the prior (experiments/trajectory_design),
  * four held-out members of the type, drawn here by this script's own implementation of the prior's laws
    (numpy, seeds 101-104) around its two listed sensors - not the design's members.
Each design's prediction on every test sensor comes from `gyrosid design --evaluate`. Cached under --work;
writes results/summary.json and results/summary.md.
"""
import argparse
import json
import os
import subprocess
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SWEEP = os.path.join(ROOT, "experiments", "trajectory_design", "seed_sweep.py")
FLIGHTS = ("short", "medium", "long")

# The prior's laws (configs/priors/open_loop_fog_type.yaml): log-normal factors, one per path and member.
LAWS = {
    "open_loop_fog.yaml": {"scale_factor.surface.error_ppm": 0.3, "bias.temperature.coefficients_dph": 0.4,
                           "noise.white_dph_at_1hz": 0.4, "thermal.tau_s": 0.4},
    "open_loop_fog_drift.yaml": {"scale_factor.surface.error_ppm": 0.3, "bias.temperature.coefficients_dph": 0.4,
                                 "noise.white_dph_at_1hz": 0.4, "noise.gauss_markov.0.sigma_dph": 0.4,
                                 "noise.gauss_markov.0.tau_s": 0.5, "noise.rrw_dph_rt_h": 0.5, "thermal.tau_s": 0.4,
                                 "thermal.coil_tau_s": 0.5},
}
BASES = {"open_loop_fog.yaml": os.path.join(ROOT, "configs", "sensors", "open_loop_fog.yaml"),
         "open_loop_fog_drift.yaml": os.path.join(ROOT, "configs", "priors", "open_loop_fog_drift.yaml")}


def scale(node, factor):
    return [scale(x, factor) for x in node] if isinstance(node, list) else node * factor


def held_out_member(base, seed, path):
    doc = yaml.safe_load(open(BASES[base]))
    rng = np.random.default_rng(seed)
    for key, log_sd in LAWS[base].items():
        parts = key.split(".")
        parent = doc
        for p in parts[:-1]:
            parent = parent[int(p)] if isinstance(parent, list) else parent[p]
        last = int(parts[-1]) if isinstance(parent, list) else parts[-1]
        parent[last] = scale(parent[last], float(np.exp(log_sd * rng.standard_normal())))
    doc["name"] = "held-out %s unit (seed %d)" % (base.split(".")[0], seed)
    yaml.safe_dump(doc, open(path, "w"), sort_keys=False)
    return path


def run(argv, product=None):
    if product is None or not os.path.exists(product):
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    return product


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gyrosid", default=os.path.join(ROOT, "build", "gyrosid"))
    ap.add_argument("--seeds", default="1-3")
    ap.add_argument("--work", default="/tmp/gyrosid-design-under-prior")
    ap.add_argument("--model", default="rbf", help="the designs' model (gyrosid design --model); their calibration.yaml calibrates every recording")
    ap.add_argument("--trajectories", default="all", help="semicolon-separated names of the table's columns to run (default all)")
    ap.add_argument("--tag", default="summary", help="results/<tag>.json and .md")
    ap.add_argument("--design-seed", type=int, default=1, help="the designs' seed (the optimiser's start and path)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    g = a.gyrosid
    designs, design_time = {}, {}
    for name, source in (("sensor", ["--sensor", "builtin:sensors/open_loop_fog.yaml"]),
                         ("prior", ["--prior", "builtin:priors/open_loop_fog_type.yaml"]),
                         ("prior_worst_half", ["--prior", "builtin:priors/open_loop_fog_type.yaml", "--set", "prior.worst_share=0.5"])):
        d = os.path.join(a.work, "design_" + name)
        if not os.path.exists(os.path.join(d, "design.json")):
            start = time.time()
            run([g, "--quiet", "design", "--budget-min", "60", "--model", a.model, "--seed", str(a.design_seed), "--out", d] + source)
            json.dump({"s": time.time() - start}, open(os.path.join(d, "time.json"), "w"))
        designs[name] = os.path.join(d, "trajectory.yaml")
        design_time[name] = json.load(open(os.path.join(d, "time.json")))["s"]
    calibration = os.path.join(a.work, "design_sensor", "calibration.yaml")
    trajectories = {"design (sensor)": (designs["sensor"], calibration), "design (prior)": (designs["prior"], calibration),
                    "design (prior, worst half)": (designs["prior_worst_half"], calibration),
                    "dual scan": ("builtin:trajectories/dual_scan.yaml", calibration),
                    "8-h soak, classical": ("builtin:trajectories/classical_soak.yaml", "builtin:calibration/classical.yaml")}
    sensors = {"other_fog (independent)": os.path.join(ROOT, "experiments", "trajectory_design", "other_fog.yaml")}
    for base, seed in (("open_loop_fog.yaml", 101), ("open_loop_fog.yaml", 102), ("open_loop_fog_drift.yaml", 103), ("open_loop_fog_drift.yaml", 104)):
        sensors["type unit %d (%s)" % (seed, base.split(".")[0])] = held_out_member(base, seed, os.path.join(a.work, "unit_%d.yaml" % seed))
    summary = {"design_time_s": design_time, "seeds": a.seeds, "sensors": {}}
    for sname, spath in sensors.items():
        tag = os.path.splitext(os.path.basename(spath))[0]
        ev = os.path.join(a.work, "evaluate_designs_" + tag)
        run([g, "--quiet", "design", "--evaluate", designs["sensor"], designs["prior"], designs["prior_worst_half"], "builtin:trajectories/dual_scan.yaml",
             "--model", a.model, "--sensor", spath, "--out", ev], os.path.join(ev, "evaluation.json"))
        predicted = json.load(open(os.path.join(ev, "evaluation.json")))["trajectories"]
        row = {}
        for tname, (tpath, cal) in trajectories.items():
            if a.trajectories != "all" and tname not in a.trajectories.split(";"):
                continue
            out = os.path.join(a.work, "sweep_%s_%s_%s.json" % (tag, "".join(c for c in tname if c.isalnum()), a.seeds))
            run(["/usr/bin/python3", SWEEP, g, tag + "_" + tname.replace(" ", "_").replace(",", "").replace("(", "").replace(")", ""), tpath,
                 "--seeds", a.seeds, "--long", "--sensor", spath, "--calibration", cal, "--work", os.path.join(a.work, "sweeps"), "--out", out])
            per_seed = json.load(open(out))
            row[tname] = {"achieved_m": {f: float(np.mean([s[f]["cof_m"] for s in per_seed.values()])) for f in FLIGHTS},
                          "sd_m": {f: float(np.std([s[f]["cof_m"] for s in per_seed.values()], ddof=1)) for f in FLIGHTS}}
            if tpath in predicted:
                row[tname]["predicted_m"] = {f: predicted[tpath]["flights"][f]["cof_m"] for f in FLIGHTS}
        summary["sensors"][sname] = row
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    json.dump(summary, open(os.path.join(HERE, "results", a.tag + ".json"), "w"), indent=1)
    lines = table(summary) + [""] + aggregate(summary) if a.trajectories == "all" else achieved_table(summary)
    open(os.path.join(HERE, "results", a.tag + ".md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print("design time: %s" % design_time)


DESIGNS = ("design (sensor)", "design (prior)", "design (prior, worst half)")


def table(summary):
    lines = ["| test sensor | flight | " + " | ".join(DESIGNS) + " | dual scan | soak, classical | " +
             " | ".join("%s / dual" % d.replace("design ", "") for d in DESIGNS) + " | prior: predicted / achieved |",
             "|---" * (6 + len(DESIGNS) + 1) + "|"]
    for sname, row in summary["sensors"].items():
        for f in FLIGHTS:
            v = {t: row[t]["achieved_m"][f] for t in row}
            pr = row["design (prior)"]
            lines.append("| %s | %s | %s | %.3g | %.3g | %s | %.2f |" % (
                sname, f, " | ".join("%.3g" % v[d] for d in DESIGNS), v["dual scan"], v["8-h soak, classical"],
                " | ".join("%.2fx" % (v["dual scan"] / v[d]) for d in DESIGNS), pr["predicted_m"][f] / pr["achieved_m"][f]))
    return lines


def achieved_table(summary):
    """The mean criterion of fit of each trajectory run (a run with --trajectories)."""
    names = list(next(iter(summary["sensors"].values())))
    lines = ["| test sensor | flight | " + " | ".join(names) + " |", "|---" * (2 + len(names)) + "|"]
    for sname, row in summary["sensors"].items():
        for f in FLIGHTS:
            lines.append("| %s | %s | %s |" % (sname, f, " | ".join("%.3g" % row[t]["achieved_m"][f] for t in names)))
    return lines


def aggregate(summary):
    lines = ["| design | geometric mean gain over the dual scan | flights lost to the dual scan | worst gain | flights won against the soak | prediction within 1.5x |",
             "|---|---|---|---|---|---|"]
    for d in DESIGNS:
        gains, soak, within = [], [], []
        for row in summary["sensors"].values():
            for f in FLIGHTS:
                gains.append(row["dual scan"]["achieved_m"][f] / row[d]["achieved_m"][f])
                soak.append(row["8-h soak, classical"]["achieved_m"][f] / row[d]["achieved_m"][f])
                r = row[d]["predicted_m"][f] / row[d]["achieved_m"][f]
                within.append(1 / 1.5 <= r <= 1.5)
        n = len(gains)
        lines.append("| %s | %.2fx | %d of %d | %.2fx | %d of %d | %d of %d |" % (
            d, float(np.exp(np.mean(np.log(gains)))), sum(g < 1 for g in gains), n, min(gains), sum(s > 1 for s in soak), n, sum(within), n))
    return lines

if __name__ == "__main__":
    main()
