#!/usr/bin/env python3
"""The floor of screening a doubled Shupe coefficient from a unit's 15-min recording (issue 33's recall target).

The best any test can do for "this unit's Shupe coefficient k is out of family" from one recording, given the lot
(every other term held to the lot's prior), is a z-test on k's estimate with the lot's prior on the other terms and
none on k. Its sd is the recording's own information on k given the rest:
    1 / sd_data^2 = 1 / var_post - 1 / var_lot,   var_post = (1 - data_share) var_lot,
with data_share the share of k's information that came from the recording (`calibrate --prior`'s summary,
model/greybox_fit.h) and var_lot the lot's variance of k. A doubled unit (2 k_u) against the lot N(mu, var_lot):
    z = (2 k_u - mu) / sqrt(var_lot + sd_data^2),   power = Phi(z - z_alpha)  (one-sided, the upper tail).
z_alpha at alpha = 0.01 for a Shupe-only test, and at alpha / 5 for `lot screen`'s Bonferroni over its four physics
tests and the noise. Every non-training unit of screening lot 100 (run.py --parts screen; screen_check.sh's lots,
learned from 50 dual scans with the 15-min null) is calibrated with the lot's prior from its 15-min recording and its
k doubled on paper; the planted doubled units are taken as they are. Writes results/shupe_floor.md.

    /usr/bin/python3 experiments/production_lot/shupe_floor.py --gyrosid /tmp/gyrosid-copy [--work /tmp/gyrosid-production-lot]
"""
import argparse
import json
import math
import os
import subprocess
from statistics import NormalDist

HERE = os.path.dirname(os.path.abspath(__file__))


def power(z, alpha):
    return NormalDist().cdf(z - NormalDist().inv_cdf(1.0 - alpha))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gyrosid", required=True)
    ap.add_argument("--work", default="/tmp/gyrosid-production-lot")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    rows = []
    for fam in "AB":
        lot_file = os.path.join(a.work, "screen_check", "lot_%s.json" % fam)
        pop = json.load(open(lot_file))["population"]
        k = [i for i, c in enumerate(pop["coordinates"]) if c["group"] == "shupe"][0]
        mu, var_lot = pop["mean"][k], pop["sd"][k] ** 2
        defects = {int(u): d for u, d in json.load(open(os.path.join(a.work, fam, "lot100_n200", "defects.json"))).items()}
        for u in range(50, 200):
            unit = os.path.join(a.work, fam, "lot100_n200", "u%05d" % u)
            out = os.path.join(a.work, "shupe_floor", fam, "u%05d.json" % u)
            if not os.path.exists(out):
                os.makedirs(os.path.dirname(out), exist_ok=True)
                subprocess.run([a.gyrosid, "--quiet", "calibrate", "--recording", os.path.join(unit, "short.csv"), "--prior", lot_file,
                                "--out", out], check=True, capture_output=True)
            share = json.load(open(out))["summary"]["details"]["data_share"]["shupe"]
            var_post = (1.0 - share) * var_lot
            sd_data = math.sqrt(1.0 / max(1e-300, 1.0 / var_post - 1.0 / var_lot))
            truth = json.load(open(os.path.join(unit, "truth.json")))
            planted = defects.get(u) == "shupe_doubled"
            if defects.get(u) and not planted:
                continue
            doubled = truth["shupe_dph_per_c_per_min"] * (1.0 if planted else 2.0)
            z = (doubled - mu) / math.sqrt(var_lot + sd_data ** 2)
            rows.append({"family": fam, "unit": u, "planted": planted, "share": share, "sd_data": sd_data, "sd_lot": math.sqrt(var_lot),
                         "mu": mu, "doubled": doubled, "z": z, "power_001": power(z, 0.01), "power_bonf": power(z, 0.01 / 5)})
    md = ["# The floor of screening a doubled Shupe coefficient from 15-min recordings", "",
          "`experiments/production_lot/shupe_floor.py` (see its docstring for the formula). Per family: the lot's Shupe mean and sd,",
          "the 15-min recording's own sd on k given the lot's prior on the other terms (median over units), and the best test's",
          "power at alpha 0.01 (a Shupe-only test) and at 0.01 / 5 (lot screen's Bonferroni), averaged over every clean unit",
          "with its k doubled on paper, and for the planted doubled units.", "",
          "| family | lot's k, mean +- sd | data share of k (median) | sd from the recording (median) | mean power, alpha 0.01 | mean power, alpha 0.002 | planted units: z, power at 0.002 |",
          "|---|---|---|---|---|---|---|"]
    summary = {}
    for fam in "AB":
        r = [x for x in rows if x["family"] == fam]
        clean = [x for x in r if not x["planted"]]
        med = lambda v: sorted(v)[len(v) // 2]
        planted = "; ".join("unit %d: z %.2f, %.0f %%" % (x["unit"], x["z"], 100 * x["power_bonf"]) for x in r if x["planted"])
        summary[fam] = {"units": len(clean), "power_001": sum(x["power_001"] for x in clean) / len(clean),
                        "power_bonf": sum(x["power_bonf"] for x in clean) / len(clean)}
        md.append("| %s | %.3g +- %.3g | %.2f | %.3g | %.0f %% | %.0f %% | %s |" % (
            fam, r[0]["mu"], r[0]["sd_lot"], med([x["share"] for x in clean]), med([x["sd_data"] for x in clean]),
            100 * summary[fam]["power_001"], 100 * summary[fam]["power_bonf"], planted))
    md.append("")
    os.makedirs(a.results, exist_ok=True)
    with open(os.path.join(a.results, "shupe_floor.md"), "w") as f:
        f.write("\n".join(md))
    with open(os.path.join(a.results, "shupe_floor.json"), "w") as f:
        json.dump({"summary": summary, "units": rows}, f, indent=1)
    print("\n".join(md))


if __name__ == "__main__":
    main()
