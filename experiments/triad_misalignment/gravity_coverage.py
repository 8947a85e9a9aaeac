#!/usr/bin/python3
"""reference=gravity's intervals on the 20 synthetic hand-turned sessions of import_imutk.synthetic_session (planted
T K): the spread of (estimate - planted) / sigma over the nine entries, the 1-sigma coverage and the fraction inside
3 sigma. --exact-accel writes the accelerometer noise-free (its calibration then exact), which separates the holds'
own noise (modelled, solvers/triad/gravity_turns.h) from the accelerometer calibration's error (shared by every hold,
not modelled).

    experiments/triad_misalignment/gravity_coverage.py --gyrosid build/gyrosid [--exact-accel] [--out /tmp/gravity_coverage]
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import import_imutk as tk  # noqa: E402


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--gyrosid", default=os.path.join(HERE, "..", "..", "build", "gyrosid"))
    p.add_argument("--exact-accel", action="store_true")
    p.add_argument("--out", default="/tmp/gravity_coverage")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    tag = "exact" if a.exact_accel else "noisy"
    zs, errs = [], []
    for k in range(1, 21):
        ts, gs, accs, planted = tk.synthetic_session(seed=k)
        holds = tk.static_intervals(ts, accs)  # found on the noisy accelerometer either way
        if a.exact_accel:
            accs = tk.synthetic_session(seed=k, noise_counts=0.0)[2]
        rec = os.path.join(a.out, "%s_seed%d.csv" % (tag, k))
        tk.write_recording(rec, ts, gs, tk.accel_calibration(accs, holds)[1](accs), holds, "synthetic seed %d" % k, turns=True)
        model = rec[:-4] + ".json"
        subprocess.run([a.gyrosid, "calibrate", "--model", "triad", "--recording", rec, "--out", model], check=True,
                       capture_output=True, env=dict(os.environ, GYROSID_QUIET="1"))
        j = json.load(open(model))
        m = np.array([[np.nan if v is None else v for v in r] for r in j["misalignment"]["matrix"]], float)
        s = np.array([[np.nan if v is None else v for v in r] for r in j["misalignment"]["sigma"]], float)
        zs.append(((m + np.eye(3) - planted) / s).ravel())
        errs.append(np.abs(m + np.eye(3) - planted).max())
    z = np.array(zs)
    print("%s accelerometer: z sd %.2f (per entry %s), 1-sigma coverage %.2f, inside 3 sigma %.3f, max error %.2e" % (
        tag, z.std(), np.round(z.std(axis=0), 2), np.mean(np.abs(z) <= 1), np.mean(np.abs(z) <= 3), max(errs)))


if __name__ == "__main__":
    main()
