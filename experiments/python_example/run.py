#!/usr/bin/env python3
"""gyrosid from Python, notebook style: simulate the reference FOG on the dual scan, characterise its noise,
calibrate a classical and an RBF model, compare them on held-out data and by the criterion of fit, and save a
model the `gyrosid` command reads. Every step runs in-process through the bindings (python/gyrosid).

    PYTHONPATH=build/python /usr/bin/python3 experiments/python_example/run.py [--out experiments/python_example/results]
"""
import argparse
import json
import os

import numpy as np

import gyrosid

HERE = os.path.dirname(os.path.abspath(__file__))


def rms_dph(x):
    return float(np.sqrt(np.mean(np.square(x))) * 3600.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    # 1. Recordings: a noisy dual scan to train on, another seed to hold out, a static run for the noise.
    train = gyrosid.simulate(trajectory="builtin:trajectories/dual_scan.yaml", seed=1)
    held_out = gyrosid.simulate(trajectory="builtin:trajectories/dual_scan.yaml", seed=2)
    static = gyrosid.simulate(trajectory="builtin:trajectories/static_2h.yaml", seed=3)
    print("recordings: %d, %d and %d samples" % (len(train), len(held_out), len(static)))

    # 2. Noise: Allan deviation of the static run's gyro - reference, in deg/h.
    dt = float(static["t_s"][1] - static["t_s"][0])
    noise = gyrosid.allan((static["gyro_dps"] - static["ref_rate_dps"]) * 3600.0, dt_s=dt)
    print("angle random walk %.4f deg/sqrt(h) (the sensor's 10 deg/h at 1 Hz is %.4f)" % (noise["arw_deg_rt_h"], 10 / 60))

    # 3. Two calibrations of the same recording.
    models = {
        "classical": gyrosid.calibrate(train, model="classical"),
        "rbf": gyrosid.calibrate(train, model="rbf", solver="nlopt"),
    }
    results = {"angle_random_walk_deg_rt_h": noise["arw_deg_rt_h"]}
    for name, model in models.items():
        compensated = gyrosid.compensate(model, held_out)
        results[name] = {
            "held_out_rms_dph": rms_dph(compensated["compensated_dps"] - held_out["ref_rate_dps"]),
            "fit_time_s": model.summary["time_s"],
            "short_m": gyrosid.cof(model, trajectory="short")["end_error_m"],
        }
        print("%-9s held-out rms %.3f deg/h, short flight %.3f m" % (name, results[name]["held_out_rms_dph"], results[name]["short_m"]))
    results["raw_gyro_held_out_rms_dph"] = rms_dph(held_out["gyro_dps"] - held_out["ref_rate_dps"])

    # 4. A model for the command line: `gyrosid cof --model rbf.json ...` reads it.
    models["rbf"].save(os.path.join(args.out, "rbf.json"))
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("wrote %s/results.json and rbf.json" % args.out)


if __name__ == "__main__":
    main()
