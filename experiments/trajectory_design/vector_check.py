#!/usr/bin/env python3
"""The seeds' end-position error vectors against the predicted distribution N(m, C), per flight.

    vector_check.py EVALUATION.json CHECK.json [NAME=TRAJECTORY ...] [--flights short,medium] [--draws 200000]

EVALUATION.json: `gyrosid design --evaluate` (per flight `bias_ned_m` m and `noise_covariance_ned_m2` C = S Sigma S');
CHECK.json: predictor_check.py's output (per seed the NED error vector at the flight's end), or seed_sweep.py's
(then NAME is the sweep's name, given as NAME=TRAJECTORY). NAME=TRAJECTORY maps a
check's name to the evaluation's trajectory key (default: the name's `trajectory` as given to predictor_check).

Per flight it reports, on C's principal axes, the predicted and achieved standard deviations (the achieved about the
seeds' mean, n-1), the achieved mean against m, and three tests of the prediction that do not use the seeds' own
spread as the yardstick:
  - spread:  k^2 = sum_s (e_s - mean)' C^-1 (e_s - mean) / (3 (n-1)), chi^2_{3(n-1)} / (3(n-1)) if C is right;
  - mean:    D^2 = n (mean - m)' C^-1 (mean - m), chi^2_3 if m and C are right;
  - the criterion's mean over n seeds, mean_s |e_s|, against its distribution under N(m, C) (Monte Carlo):
    the fraction of n-seed means at or below the achieved (with m, and with m = 0).
The long flight is left out by default: its seeds' vectors are the 2-h end positions, not the 1-h criterion.
"""
import argparse
import json
import math

import numpy as np
from scipy import stats


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("evaluation")
    ap.add_argument("check")
    ap.add_argument("names", nargs="*", help="NAME=TRAJECTORY: the evaluation's key for a check's name")
    ap.add_argument("--flights", default="short,medium")
    ap.add_argument("--draws", type=int, default=200000)
    a = ap.parse_args()
    ev = json.load(open(a.evaluation))["trajectories"]
    check = json.load(open(a.check))
    keys = dict(n.split("=", 1) for n in a.names)
    if check and "achieved" not in next(iter(check.values())):  # seed_sweep.py: {seed: {flight: {error_ned_m}}}
        seeds = sorted(check, key=int)
        check = {n: {"achieved": {f: {"vectors": [check[s][f]["error_ned_m"] for s in seeds]} for f in ("short", "medium")}} for n in keys}
    rng = np.random.default_rng(1)
    for name, row in check.items():
        key = keys.get(name)
        if key is None:
            continue
        for f in a.flights.split(","):
            p = ev[key]["flights"][f]
            m = np.array(p["bias_ned_m"])
            c = np.array(p["noise_covariance_ned_m2"])
            v = np.array(row["achieved"][f]["vectors"])
            n = len(v)
            mean = v.mean(0)
            lam, u = np.linalg.eigh(c)
            lam = np.maximum(lam, 1e-30)
            # on C's principal axes (largest first)
            z = (v - mean) @ u
            sd_ach = np.sqrt((z ** 2).sum(0) / (n - 1))
            ci = u @ np.diag(1 / lam) @ u.T
            k2 = sum((e - mean) @ ci @ (e - mean) for e in v) / (3 * (n - 1))
            dof = 3 * (n - 1)
            p_k2 = stats.chi2.cdf(k2 * dof, dof)
            d2 = n * (mean - m) @ ci @ (mean - m)
            p_d2 = stats.chi2.sf(d2, 3)
            crit = np.linalg.norm(v, axis=1).mean()
            crit_se = np.linalg.norm(v, axis=1).std(ddof=1) / math.sqrt(n)
            root = u @ np.diag(np.sqrt(lam)) @ u.T

            def means(bias):
                d = rng.standard_normal((a.draws, n, 3)) @ root.T + bias
                return np.linalg.norm(d, axis=2).mean(1)
            with_m, no_m = means(m), means(np.zeros(3))
            print("%s %s (n = %d)" % (name, f, n))
            print("  principal sd predicted %s achieved %s (m)" % (np.sqrt(lam)[::-1].round(4), sd_ach[::-1].round(4)))
            print("  m on the axes %s, achieved mean %s (se on the axes %s)" % ((m @ u)[::-1].round(4), (mean @ u)[::-1].round(4),
                                                                           (np.sqrt(lam / n))[::-1].round(4)))
            print("  |m| %.4g, |mean| %.4g; spread k = %.3f (P(k' <= k) = %.3f, chi2 %d dof); mean test D2 = %.2f (p = %.3g)" % (
                np.linalg.norm(m), np.linalg.norm(mean), math.sqrt(k2), p_k2, dof, d2, p_d2))
            print("  criterion mean %.4g +- %.2g (the seeds' se); predicted E|m+Sd| %.4g (n-seed mean sd %.3g, P(<= achieved) %.3f); "
                  "m = 0: %.4g (sd %.3g, P %.3f)" % (crit, crit_se, with_m.mean(), with_m.std(), (with_m <= crit).mean(),
                                                       no_m.mean(), no_m.std(), (no_m <= crit).mean()))


if __name__ == "__main__":
    main()
