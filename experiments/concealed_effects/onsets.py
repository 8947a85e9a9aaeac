#!/usr/bin/env python3
"""Changes at odd times on the independent generator (issue 34, class 1): a bias step or a trend that sets in
at a stated fraction of the record (the suite's own steps and ramps sit between 30 % and 70 %), and the
independent controls, run by one or more gyrosid binaries on the same recordings in the same run.

A change is right when explain says `unexplained_residual` and localises it: a reported span that, widened by
600 s, holds the change (the suite's rule, independent_cases.score); a control is right when nothing is reported.
A change that is not right but listed as an alternative of what explain named is counted apart (`as_alternative`):
explain then says the recording cannot tell the two apart, which is not the suite's right answer.

    onsets.py --gyrosid build/gyrosid --tag main --out /tmp/onsets [--seeds 1,2,3] [--controls]
"""
import argparse
import csv
import os
import sys

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import independent_cases as ic  # noqa: E402

# (effect, magnitude in sigma of its unabsorbed rms, where it starts as a fraction of the record)
CHANGES = [("bias_step", 0.5, 0.07), ("bias_ramp", 0.5, 0.55), ("bias_ramp", 0.5, 0.7), ("bias_step", 0.25, 0.2),
           ("bias_step", 0.5, 0.12), ("bias_step", 1.0, 0.88), ("bias_step", 0.5, 0.93), ("bias_step", 1.0, 0.42),
           ("bias_ramp", 0.5, 0.8), ("bias_ramp", 1.0, 0.9), ("bias_ramp", 0.5, 0.15)]


def jobs(out, seeds, controls):
    for eid, m, at in CHANGES:
        for seed in seeds:
            sd = 8500 + seed + int(100 * m) + int(1000 * at)
            yield {"generator": "independent", "group": "outside", "case": "%s@%s@%s" % (eid, m, at), "seed": sd,
                   "spec": {"effects": [{"id": eid, "magnitude": m, "at": at}]},
                   "dir": os.path.join(out, "cases", "%s_%s_%s_%d" % (eid, m, at, sd))}
    if controls:  # the suite's own (config.yaml, independent.controls)
        cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))["independent"]
        yield from (j for j in ic.jobs(cfg, out, 1) if j["group"] == "control")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ic.add_binary_arguments(p)
    p.add_argument("--seeds", default="1,2,3", help="seeds per change (comma-separated)")
    p.add_argument("--controls", action="store_true", help="also the 24 independent controls")
    a = p.parse_args()
    rows = []
    for job in jobs(a.out, [int(s) for s in a.seeds.split(",")], a.controls):
        truth = ic.build(job)
        ex = ic.explained(a.gyrosid, job, a.tag)
        row = ic.score(job, truth, ex, job["dir"])
        row["right"] = row.get("localised", False) if job["group"] == "outside" else ex["verdict"] == "no_missing_physics"
        row["random_walk_in_noise"] = any(t["id"] == "rate_random_walk" for t in ex["noise"]["terms"])
        planted = {e["id"] for e in job["spec"].get("effects", [])}
        row["as_alternative"] = not row["right"] and any(planted & set(e["alternatives"]) for e in ex["effects"])
        rows.append(row)
        print("%-24s %5d %-22s %-14s %-40s right=%s %.1f s" % (job["case"], job["seed"], ex["verdict"], row["named"], row["unexplained"],
                                                              row["right"], ex["run_time_s"]), flush=True)
    keys = ["group", "case", "seed", "verdict", "named", "unexplained", "right", "as_alternative", "random_walk_in_noise", "run_time_s"]
    with open(os.path.join(a.out, a.tag + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    for group in ("outside", "control"):
        g = [r for r in rows if r["group"] == group]
        if g:
            times = sorted(r["run_time_s"] for r in g)
            print("%s: %d/%d right, %d more as an alternative of what was named; run time median %.1f s, max %.1f s" %
                  (group, sum(r["right"] for r in g), len(g), sum(r["as_alternative"] for r in g), times[len(times) // 2], times[-1]))


if __name__ == "__main__":
    main()
