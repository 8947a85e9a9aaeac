#!/usr/bin/env python3
"""Well-known peers on the same recordings: scikit-learn's GaussianProcessRegressor (anisotropic RBF kernel
plus a white-noise kernel, hyper-parameters by maximum marginal likelihood, on the largest random subset the
time budget allows) and KernelRidge (RBF kernel, alpha and gamma tuned by 3-fold cross-validation on a grid).
Both learn the rate error (deg/h) from the inputs gyrosid's RBF uses - measured rate and temperature,
normalised to [-1, 1] over the training recording.

    peers.py --train rec.csv --eval grid.csv [--eval heldout.csv ...] --out peers.json [--gp-subset 2000]

For each evaluation recording it writes the rms and 95 % coverage (GP: its own predictive sigma) of
predicted - true error, with the fit time.
"""
import argparse
import json
import os
import sys
import time

import numpy as np
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel
from sklearn.kernel_ridge import KernelRidge
from sklearn.model_selection import GridSearchCV, KFold

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import rate_error_dph, read_recording  # noqa: E402


def inputs_and_error(path):
    _, c = read_recording(path)
    return np.column_stack([c["gyro_dps"], c["temp_c"]]), rate_error_dph(c)


def fit_krr(x, y, subset, rng):
    """KernelRidge on a random subset, alpha and gamma by 3-fold CV over a log grid (the tuned peer)."""
    idx = rng.choice(len(x), size=min(subset, len(x)), replace=False)
    grid = {"alpha": [1e-3, 1e-2, 1e-1, 1.0, 10.0], "gamma": [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0]}
    search = GridSearchCV(KernelRidge(kernel="rbf"), grid, cv=KFold(3, shuffle=True, random_state=0),
                          scoring="neg_mean_squared_error", n_jobs=1)
    search.fit(x[idx], y[idx])
    return search.best_estimator_, {"alpha": search.best_params_["alpha"], "gamma": search.best_params_["gamma"],
                                    "samples_used": int(len(idx))}


def fit_gp(x, y, subset, rng):
    idx = rng.choice(len(x), size=min(subset, len(x)), replace=False)
    kernel = ConstantKernel(1.0, (1e-3, 1e3)) * RBF(length_scale=[0.3, 0.5], length_scale_bounds=(1e-3, 1e2)) + \
        WhiteKernel(0.1, (1e-8, 1e1))
    gp = GaussianProcessRegressor(kernel=kernel, normalize_y=True, random_state=0).fit(x[idx], y[idx])
    return gp, {"kernel": str(gp.kernel_), "samples_used": int(len(idx))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--train", required=True)
    ap.add_argument("--eval", action="append", required=True, help="recording to score (repeatable)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--gp-subset", type=int, default=2000)
    ap.add_argument("--krr-subset", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    x, y = inputs_and_error(a.train)
    lo, hi = x.min(axis=0), x.max(axis=0)
    norm = lambda v: 2.0 * (v - lo) / (hi - lo) - 1.0  # noqa: E731
    rng = np.random.default_rng(a.seed)
    evals = [(p,) + inputs_and_error(p) for p in a.eval]
    out = {}
    for name, fit in (("krr", fit_krr), ("gp", fit_gp)):
        start = time.time()
        model, info = fit(norm(x), y, a.krr_subset if name == "krr" else a.gp_subset, rng)
        info["time_s"] = time.time() - start
        info["scores"] = {}
        for path, xe, ye in evals:
            if name == "gp":
                pred, sd = model.predict(norm(xe), return_std=True)
                # return_std includes the white-noise kernel's variance: remove it for the function's sigma.
                noise = model.kernel_.k2.noise_level * model._y_train_std ** 2
                sd = np.sqrt(np.maximum(sd ** 2 - noise, 0.0))
            else:
                pred, sd = model.predict(norm(xe)), None
            d = pred - ye
            score = {"rms_dph": float(np.sqrt(np.mean(d * d)))}
            if sd is not None:
                score["coverage_95"] = float(np.mean(np.abs(d) <= 1.96 * sd))
            info["scores"][os.path.basename(path)] = score
        out[name] = info
        sys.stderr.write("  %s: %.1f s, %s\n" % (name, info["time_s"], info["scores"]))
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(out, f, indent=1)
    os.replace(tmp, a.out)


if __name__ == "__main__":
    main()
