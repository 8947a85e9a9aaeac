#!/usr/bin/env python3
"""Issue 32, item 3 (defaults that agree): does `gyrosid design` with only a budget design for the calibration a
new user then runs? Designs of 60 min for the reference sensor under several --model / --criterion choices, and
the 62-min dual scan, are simulated on the reference sensor and on other_fog.yaml (which the designs are not
given), calibrated as `gyrosid calibrate` does without options on a noisy recording (its preset,
rbf_noisy.yaml: the hybrid model), and scored by `gyrosid cof` on the three flights (seed_sweep.py).

    defaults_check.py --gyrosid G [--seeds 1-3] [--work /tmp/gyrosid-defaults-check] --out results/defaults_check.md
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DESIGNS = {  # name: design arguments beside --budget-min 60
    "rbf, cof (the old default)": ["--model", "rbf"],
    "hybrid, cof": ["--model", "hybrid"],
    "hybrid, cof_minimax": ["--model", "hybrid", "--criterion", "cof_minimax"],
}
SENSORS = {"reference (designed for)": "builtin:sensors/open_loop_fog.yaml", "other_fog (not given)": os.path.join(HERE, "other_fog.yaml")}
FLIGHTS = ("short", "medium", "long")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gyrosid", required=True)
    ap.add_argument("--seeds", default="1-3")
    ap.add_argument("--work", default="/tmp/gyrosid-defaults-check")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    trajectories = {"dual scan (62 min)": "builtin:trajectories/dual_scan.yaml"}
    design_s = {}
    for name, args in DESIGNS.items():
        d = os.path.join(a.work, "design_" + name.split(" (")[0].replace(", ", "_"))
        if not os.path.exists(os.path.join(d, "trajectory.yaml")):
            t0 = time.time()
            subprocess.run([a.gyrosid, "--quiet", "design", "--budget-min", "60", "--out", d] + args, check=True, stdout=subprocess.DEVNULL)
            design_s[name] = time.time() - t0
        j = json.load(open(os.path.join(d, "design.json")))
        trajectories["design: " + name] = os.path.join(d, "trajectory.yaml")
        print("designed %-28s model %s, criterion %s%s" % (name, j["provenance"]["model"], j.get("criterion", "?"),
                                                           " in %.0f s" % design_s[name] if name in design_s else ""), flush=True)
    table = {}
    for sname, sensor in SENSORS.items():
        for tname, traj in trajectories.items():
            key = "%s_%s" % (sname.split(" ")[0], tname.replace(" ", "_").replace(",", "").replace(":", "").replace("(", "").replace(")", ""))
            out = os.path.join(a.work, key + ".json")
            if not os.path.exists(out):
                subprocess.run([sys.executable, os.path.join(HERE, "seed_sweep.py"), a.gyrosid, key, traj, "--seeds", a.seeds, "--long",
                                "--sensor", sensor, "--work", a.work, "--out", out], check=True)
            rows = json.load(open(out))
            table[(sname, tname)] = {f: math.exp(sum(math.log(r[f]["cof_m"]) for r in rows.values()) / len(rows)) for f in FLIGHTS}
            print(sname, tname, table[(sname, tname)], flush=True)
    lines = ["| test sensor | programme | short (m) | medium (m) | long (m) | against the dual scan, short / medium / long |", "|---|---|---|---|---|---|"]
    for sname in SENSORS:
        dual = table[(sname, "dual scan (62 min)")]
        for tname in trajectories:
            v = table[(sname, tname)]
            gains = " / ".join("%.2fx" % (dual[f] / v[f]) for f in FLIGHTS)
            lines.append("| %s | %s | %s | %s |" % (sname, tname, " | ".join("%.3g" % v[f] for f in FLIGHTS), gains))
    text = "Geometric means over seeds %s; calibration: rbf_noisy.yaml (what `calibrate` picks for a noisy recording).\n\n" % a.seeds
    open(a.out, "w").write(text + "\n".join(lines) + "\n")
    print(text + "\n".join(lines))


if __name__ == "__main__":
    main()
