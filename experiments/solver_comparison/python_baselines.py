#!/usr/bin/python3
"""The same calibration problem solved by general-purpose Python tools, side by side with gyrosid's solvers:
scipy.interpolate.RBFInterpolator and scikit-learn's KernelRidge and GaussianProcessRegressor (Debian's
python3-scipy and python3-sklearn).

    experiments/solver_comparison/python_baselines.py [--results experiments/solver_comparison/results]
                                                      [--training dual_11110]

Reads the training recordings, the surface grid and results.csv written by run.py; fits each baseline to
the rate error over normalised (measured rate, temperature); scores it on the same true error surface;
writes python_baselines.csv/.md with time and accuracy ratios to gyrosid's ols and best solver. Dense
kernel methods cost O(N^3) time and O(N^2) memory, so they train on a random subset where N is large (the
row says how many samples each used).
"""
import argparse
import csv
import os
import sys
import time

import numpy as np
from scipy.interpolate import RBFInterpolator
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel
from sklearn.kernel_ridge import KernelRidge

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import markdown_table, rate_error_dph, read_recording, write_csv, write_text  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def training_data(path):
    """Inputs (measured rate deg/s, temperature C) and the rate error (deg/h) of a recording."""
    _, cols = read_recording(path)
    return np.column_stack([cols["gyro_dps"], cols["temp_c"]]), rate_error_dph(cols)


def read_surface(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    x = np.array([[float(r["measured_rate_dps"]), float(r["temp_c"])] for r in rows])
    return x, np.array([float(r["true_dph"]) for r in rows])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    ap.add_argument("--training", default="dual_11110")
    ap.add_argument("--max-dense", type=int, default=3000, help="subset size for O(N^3) kernel methods")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    ours = {(r["training"], r["noise"], r["solver"]): r for r in csv.DictReader(open(os.path.join(args.results, "results.csv")))}
    rng = np.random.default_rng(args.seed)
    out = []
    for noise in ["noise_free", "white_10dph"]:
        x, y = training_data(os.path.join(args.results, "data", "train_%s_%s.csv" % (args.training, noise)))
        gx, gtrue = read_surface(os.path.join(args.results, "surfaces", args.training, noise, "ols", "surface.csv"))
        lo, hi = x.min(axis=0), x.max(axis=0)
        norm = lambda v: 2.0 * (v - lo) / (hi - lo) - 1.0  # noqa: E731
        xn, gn = norm(x), norm(gx)
        sub = rng.choice(len(xn), size=min(args.max_dense, len(xn)), replace=False)
        smooth = 0.0 if noise == "noise_free" else 1.0
        baselines = [
            ("scipy RBFInterpolator gaussian, 64 neighbours", len(xn),
             lambda: RBFInterpolator(xn, y, kernel="gaussian", epsilon=4.0, neighbors=64, smoothing=smooth * 1e-2)),
            ("scipy RBFInterpolator thin-plate, 64 neighbours", len(xn),
             lambda: RBFInterpolator(xn, y, kernel="thin_plate_spline", neighbors=64, smoothing=smooth)),
            ("sklearn KernelRidge rbf", len(sub),
             lambda: KernelRidge(kernel="rbf", gamma=8.0, alpha=1e-6 if noise == "noise_free" else 1e-1).fit(xn[sub], y[sub])),
            ("sklearn GaussianProcessRegressor (anisotropic RBF + white)", min(len(sub), 2000),
             lambda: GaussianProcessRegressor(
                 kernel=ConstantKernel(1e4) * RBF(length_scale=[0.3, 0.3]) + WhiteKernel(1e-2 if noise == "noise_free" else 100.0),
                 normalize_y=True, random_state=args.seed).fit(xn[sub[:2000]], y[sub[:2000]])),
        ]
        for name, used, make in baselines:
            start = time.time()
            model = make()
            pred = model(gn) if callable(model) and not hasattr(model, "predict") else model.predict(gn)
            seconds = time.time() - start
            d = pred - gtrue
            row = {"noise": noise, "method": name, "samples_used": used, "time_s": seconds,
                   "rms_dph": float(np.sqrt(np.mean(d * d))), "max_abs_dph": float(np.max(np.abs(d)))}
            for label in ["ols", "ceres"]:
                r = ours.get((args.training, noise, label))
                if r:
                    row["time_vs_" + label] = seconds / float(r["time_s"])
                    row["rms_vs_" + label] = row["rms_dph"] / float(r["rms_dph"])
            out.append(row)
            sys.stderr.write("  %-12s %-58s %6d samples %8.2f s  rms %8.4g deg/h\n" % (noise, name, used, seconds, row["rms_dph"]))
        for label in ["ols", "ceres", "nlopt"]:
            r = ours.get((args.training, noise, label))
            if r:
                out.append({"noise": noise, "method": "gyrosid " + label, "samples_used": len(xn), "time_s": float(r["time_s"]),
                            "rms_dph": float(r["rms_dph"]), "max_abs_dph": max(abs(float(r["max_dph"])), abs(float(r["min_dph"])))})
    cols = ["noise", "method", "samples_used", "time_s", "rms_dph", "max_abs_dph", "time_vs_ols", "rms_vs_ols",
            "time_vs_ceres", "rms_vs_ceres"]
    write_csv(os.path.join(args.results, "python_baselines.csv"), out, cols)
    write_text(os.path.join(args.results, "python_baselines.md"),
               "# Python baselines on %s\n\nSurface rms over the same grid (deg/h); ratios are baseline / gyrosid.\n"
               "Generated by `%s`.\n\n" % (args.training, " ".join(sys.argv)) + markdown_table(out, cols))


if __name__ == "__main__":
    main()
