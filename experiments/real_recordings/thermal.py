#!/usr/bin/env python3
"""A real recording across a real temperature change: the PAN CubeSat gyro's thermal-vacuum cooling run
(../shared/realdata/psim, MIT; 25 bursts of 5 s at 50 Hz while the chamber cooled from about 24 to 16 C),
calibrated by gyrosid and by PX4's thermal calibration on the same training bursts, scored on held-out bursts.

PX4's thermal calibration (src/modules/temperature_compensation in PX4-Autopilot) fits each gyro axis's
offset as a cubic in (T - T_ref) over the log; here it is refitted in numpy the same way: least squares of
the mean-removed gyro on 1, dT, dT^2, dT^3 with T_ref the training mid-temperature. gyrosid: the default
`gyrosid calibrate` on the training recording (it sees a static gyro - a held rate - and fits what the
temperature determines), then `gyrosid compensate` on the held-out one.

Two splits, both over whole bursts: interleaved (odd bursts held out: interpolation within the trained
temperatures) and the last third held out (the coldest bursts: extrapolation past them).
Writes results/thermal.md.

    experiments/real_recordings/thermal.py [--gyrosid build/gyrosid] [--work /tmp/real_recordings/thermal]
"""
import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
from gyrosid_experiments import add_gyrosid_argument, fmt, markdown_table, read_recording, write_recording, write_text  # noqa: E402
from realdata import realdata, run_timed  # noqa: E402


def bursts(t):
    """Burst index of every sample: a new burst wherever the time jumps by more than 10 s."""
    return np.concatenate([[0], np.cumsum(np.diff(t) > 10.0)])


def px4_cubic(train, test):
    """PX4-style thermal offset: cubic in T - T_ref by least squares; returns test residual (deg/h)."""
    t_ref = 0.5 * (train["temp_c"].min() + train["temp_c"].max())
    def design(c):
        d = c["temp_c"] - t_ref
        return np.column_stack([np.ones_like(d), d, d * d, d * d * d])
    coef, *_ = np.linalg.lstsq(design(train), train["gyro_dps"] * 3600.0, rcond=None)
    return test["gyro_dps"] * 3600.0 - design(test) @ coef


def subset(meta, cols, keep):
    return meta, {k: v[keep] for k, v in cols.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--work", default="/tmp/real_recordings/thermal")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    source = os.path.join(realdata(), "psim", "MATLAB", "sensor_models", "TVCtest3_7_20.csv")
    subprocess.run([sys.executable, os.path.join(HERE, "..", "cubesat_tvc", "import_psim.py"), "--source", source, "--out", a.work],
                   check=True, capture_output=True)
    rows = []
    for axis in "xyz":
        meta, cols = read_recording(os.path.join(a.work, "tvc_gyro_%s.csv" % axis))
        b = bursts(cols["t_s"])
        n = b.max() + 1
        for split, held in (("interleaved (odd bursts held out)", b % 2 == 1), ("last third held out (coldest)", b >= (2 * n) // 3)):
            name = "%s_%s" % (axis, "interleaved" if "odd" in split else "cold")
            train_path, test_path = os.path.join(a.work, name + "_train.csv"), os.path.join(a.work, name + "_test.csv")
            write_recording(train_path, *subset(meta, cols, ~held))
            write_recording(test_path, *subset(meta, cols, held))
            model = os.path.join(a.work, name + "_model.json")
            fit_s, fit_kb = run_timed([a.gyrosid, "calibrate", "--recording", train_path, "--out", model])
            compensated = os.path.join(a.work, name + "_compensated.csv")
            run_timed([a.gyrosid, "compensate", "--model", model, "--recording", test_path, "--out", compensated])
            _, comp = read_recording(compensated)
            test = {k: v[held] for k, v in cols.items()}
            ours = (comp["compensated_dps"] - comp["ref_rate_dps"]) * 3600.0
            px4 = px4_cubic({k: v[~held] for k, v in cols.items()}, test)
            raw = test["gyro_dps"] * 3600.0 - np.mean(cols["gyro_dps"][~held] * 3600.0)
            rows.append({"axis": axis, "split": split, "held-out samples": int(held.sum()),
                         "T held out (C)": "%s..%s" % (fmt(test["temp_c"].min(), 3), fmt(test["temp_c"].max(), 3)),
                         "mean only (deg/h)": fmt(np.sqrt(np.mean(raw ** 2)), 3),
                         "PX4 cubic (deg/h)": fmt(np.sqrt(np.mean(px4 ** 2)), 3),
                         "gyrosid (deg/h)": fmt(np.sqrt(np.mean(ours ** 2)), 3),
                         "gyrosid / PX4": fmt(np.sqrt(np.mean(ours ** 2)) / np.sqrt(np.mean(px4 ** 2)), 3),
                         "fit s": fmt(fit_s, 2)})
            print(rows[-1], file=sys.stderr)
    text = ["# Thermal calibration on a real cooling run: gyrosid against PX4's cubic", "",
            "Held-out rms of the rate error after compensation (the gyro is static; the constant Earth-rate projection is part "
            "of every fitted offset). 'mean only': the training mean removed. The temperature is the raw count read as the "
            "LSM6DSM register (unverified, SOURCES.md): both methods see the same temperature.", "",
            markdown_table(rows, list(rows[0].keys())), ""]
    os.makedirs(a.results, exist_ok=True)
    write_text(os.path.join(a.results, "thermal.md"), "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
