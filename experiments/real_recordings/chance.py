#!/usr/bin/env python3
"""How many display taus does the TRUE model leave outside the data's 95 % band? (the floor of the
'fitted ADEV within the band at every tau' target of issue 30.)

    experiments/real_recordings/chance.py [--gyrosid build/gyrosid] [--seeds 20] [--work /tmp/chance]

Draws ADIS16405-like static records with ../noise_identification/generator.py (independent of gyrosid):
100 Hz, 10^6 samples, white noise N = 2.42 deg/sqrt(h) and a Gauss-Markov term (56.7 deg/h, 139 s) - the
model gyrosid identified on ADIS16405 unit 2 x, less its filter term. Runs `gyrosid allan --confidence 0.95`
and counts the display taus in [0.01 s, a tenth of the record] where the true Allan deviation lies outside
the data's interval. Exact true curve for interval means: N^2/tau + (2 s^2 T / tau)(1 - T/(2 tau)(3 - 4e^-x + e^-2x)),
x = tau/T. Writes results/chance.md.
"""
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, os.path.join(HERE, "..", "noise_identification"))
import generator  # noqa: E402
from gyrosid_experiments import add_gyrosid_argument, markdown_table, write_text  # noqa: E402

DT, SAMPLES = 0.01, 10 ** 6
N = 2.42 * 60.0           # deg/h sqrt(s)
GM_SIGMA, GM_TAU = 56.7, 139.0


def true_avar(tau):
    x = tau / GM_TAU
    gm = 2.0 * GM_SIGMA ** 2 * GM_TAU / tau * (1.0 - GM_TAU / (2.0 * tau) * (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)))
    return N ** 2 / tau + gm


def misses(gyrosid, work, seed):
    rate = generator.composite(SAMPLES, DT, seed, N=N, gauss_markov=[(GM_SIGMA, GM_TAU)])
    rec = os.path.join(work, "seed%d.csv" % seed)
    with open(rec, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sample_rate_hz: 100\nt_s,ref_rate_dps,temp_c,gyro_dps\n")
        np.savetxt(f, np.column_stack([np.arange(SAMPLES) * DT, np.zeros(SAMPLES), np.full(SAMPLES, 25.0), rate / 3600.0]),
                   delimiter=",", fmt=["%.2f", "%g", "%g", "%.12g"])
    out = os.path.join(work, "seed%d" % seed)
    subprocess.run([gyrosid, "allan", "--recording", rec, "--confidence", "0.95", "--out", out], check=True, capture_output=True)
    os.remove(rec)
    hi = SAMPLES * DT / 10.0
    count = total = 0
    with open(os.path.join(out, "allan.csv")) as f:
        for p in csv.DictReader(f):
            tau = float(p["tau_s"])
            if not (0.01 * (1 - 1e-9) <= tau <= hi * (1 + 1e-9)):
                continue
            total += 1
            adev = np.sqrt(true_avar(tau))
            count += not (float(p["ci_low_dph"]) <= adev <= float(p["ci_high_dph"]))
    return count, total


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--work", default="/tmp/chance")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    counts = []
    for seed in range(1, a.seeds + 1):
        c, total = misses(a.gyrosid, a.work, seed)
        counts.append(c)
        print("seed %d: true model outside the 95 %% band at %d of %d taus" % (seed, c, total), file=sys.stderr)
    counts = np.array(counts)
    rows = [{"seeds": a.seeds, "taus in band": total, "mean taus outside": "%.2f" % counts.mean(), "median": "%g" % np.median(counts),
             "max": int(counts.max()), "records with none outside": "%d/%d" % ((counts == 0).sum(), a.seeds)}]
    text = ["# The true model against the data's 95 % band", "",
            "ADIS16405-like records from the independent generator (N 2.42 deg/sqrt(h) + Gauss-Markov 56.7 deg/h, 139 s; "
            "100 Hz, 10^6 samples): display taus from 0.01 s to a tenth of the record where the TRUE Allan deviation lies "
            "outside `gyrosid allan --confidence 0.95`'s interval.", "",
            markdown_table(rows, list(rows[0].keys())), "",
            "Per seed: " + ", ".join(str(c) for c in counts), ""]
    os.makedirs(a.results, exist_ok=True)
    write_text(os.path.join(a.results, "chance.md"), "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
