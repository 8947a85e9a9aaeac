#!/usr/bin/env python3
# Target 2's deciding pair (the dual scan and the Ipopt 62-min cof_minimax design against its posterior
# statistic) on more seeds (usage: more_seeds.py GYROSID 6,7,8,9,10), cached where run.py caches (extending config.yaml's seeds reuses them).
import argparse, json, math, os, sys
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import yaml
import run

cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))
a = argparse.Namespace(gyrosid=sys.argv[1], out=os.path.join(HERE, "results"), force=False, max_minutes=14)
st = run.Study(a, cfg)
pairs = [("dual_scan", cfg["thesis"]["dual_scan"]), ("ipopt_62_minimax_post", os.path.join(HERE, "results/work/reference/designs/ipopt_62_minimax_post/trajectory.yaml"))]
seeds = [int(s) for s in sys.argv[2].split(",")]
out = {}
for name, path in pairs:
    for s in seeds:
        out.setdefault(name, []).append(st.score("reference", cfg["sensor"], name, path, s, "best", cfg["calibrations"]["best"]))
        print(name, s, out[name][-1], flush=True)
json.dump(out, open(os.path.join(HERE, "results", "target2_seeds_%s.json" % sys.argv[2].replace(",", "_")), "w"), indent=1)
