#!/usr/bin/env python3
"""Hysteresis of other shapes on the independent generator (issue 34, class 4): loops that are not one play
operator - two plays of different widths, and a Prandtl-Ishlinskii loop whose widths spread over a range
(a Preisach-like loop that rounds off gradually) - run by one or more gyrosid binaries on the same recordings.

Right: thermal_hysteresis named, its offset (heating-branch minus cooling-branch bias, the loop's full height)
within 30 %, and the held-out excess the loop causes removed (the suite's rule: median >= 0.9).

    hysteresis_shapes.py --gyrosid build/gyrosid --tag main --out /tmp/hyst [--seeds 1,2]
"""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import independent_cases as ic  # noqa: E402

# name: the plays' half-widths (C) and weights (summing to 1: the loop's height is the planted offset)
SHAPES = {
    "one_play": {"play_c": [1.5], "play_weights": [1.0]},                     # the suite's own form (a control of the shape)
    "two_plays_0.5_4": {"play_c": [0.5, 4.0], "play_weights": [0.5, 0.5]},
    "two_plays_1_8": {"play_c": [1.0, 8.0], "play_weights": [0.35, 0.65]},
    "spread_0.2_6": {"play_c": list(np.linspace(0.2, 6.0, 12)), "play_weights": [1.0 / 12] * 12},
}
MAGNITUDES = (0.5, 1.0)
# The seed's own programme (long ramps: the loop mostly saturated), and reversals of 2-12 C inside the range.
PROGRAMMES = (None, "minor_loops")


def jobs(out, seeds):
    for programme in PROGRAMMES:
        for name, shape in SHAPES.items():
            for m in MAGNITUDES:
                for seed in seeds:
                    sd = 7600 + seed + int(100 * m) + 10 * list(SHAPES).index(name)
                    case = "%s@%s" % (name, m) + ("@" + programme if programme else "")
                    spec = {"effects": [dict(id="thermal_hysteresis", magnitude=m, **shape)]}
                    if programme:
                        spec["programme"] = programme
                    yield {"generator": "independent", "group": "effect", "case": case, "seed": sd, "spec": spec,
                           "dir": os.path.join(out, "cases", case.replace("@", "_") + "_%d" % sd)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ic.add_binary_arguments(p)
    p.add_argument("--seeds", default="1,2", help="seeds per shape and magnitude (comma-separated)")
    a = p.parse_args()
    rows = []
    for job, truth, ex, row in ic.explained_rows(a.gyrosid, a.tag, jobs(a.out, [int(s) for s in a.seeds.split(",")])):
        hit = next((e for e in ex["effects"] if e["id"] == "thermal_hysteresis"), None)
        row["widths_c"] = " ".join("%s=%.3g" % (k, v) for k, v in (hit or {}).get("parameters", {}).items() if k.startswith("width"))
        rows.append(row)
        print("%-22s %5d %-22s %-40s offset err %s excess removed %s %.1f s" % (
            job["case"], job["seed"], ex["verdict"], row["named"], "%.3f" % row["param_rel_err"] if "param_rel_err" in row else "-",
            "%.3f" % row["heldout_excess_removed"] if "heldout_excess_removed" in row else "-", ex["run_time_s"]), flush=True)
    keys = ["case", "seed", "verdict", "named", "correct", "wrong_extra", "param_rel_err", "widths_c", "heldout_excess_removed",
            "heldout_excess_removed_all", "run_time_s"]
    ic.write_rows(os.path.join(a.out, a.tag + ".csv"), rows, keys)
    for name in SHAPES:
        for programme in PROGRAMMES:
            g = [r for r in rows if r["case"].split("@")[0] == name and r["case"].split("@")[2:] == ([programme] if programme else [])]
            ex = sorted(r["heldout_excess_removed"] for r in g if "heldout_excess_removed" in r)
            print("%-18s %-12s named %d/%d, excess removed median %s min %s" % (
                name, programme or "own", sum(bool(r.get("correct")) for r in g), len(g),
                "%.3f" % ex[len(ex) // 2] if ex else "-", "%.3f" % ex[0] if ex else "-"))


if __name__ == "__main__":
    main()
