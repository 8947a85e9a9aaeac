#!/usr/bin/env python3
"""Well-known peers on the same recordings: scikit-learn's GaussianProcessRegressor (anisotropic RBF kernel
plus a white-noise kernel, hyper-parameters by maximum marginal likelihood, on the largest random subset the
time budget allows) and KernelRidge (RBF kernel, alpha and gamma tuned by 3-fold cross-validation on a grid).
Both learn the rate error (deg/h) as a function of rate and temperature, normalised to [-1, 1] over the
training recording, and are evaluated, as gyrosid's compensation is, at the measured rate.

Training input: the rate table's (reference) rate, not the measured rate. The target is measured - reference
rate, so with the measured rate as input the recording's noise is in the input as well as in the target: on a
programme that holds the rate at discrete levels (sensor C's staircase) the target is then, within a level,
an exact linear function of the input (e = 3600 (x - w_level)), and the GP's marginal likelihood is maximised
by interpolating it with no noise at all (length scale 0.004 of the half-range on the rate, white-noise level
at its 1e-8 bound, log marginal likelihood 11,884): between the levels it predicts the training mean, 151.8
deg/h held-out on staircase white 1 and white 10 seed 1 (fifth run). That is the likelihood's optimum, not an
optimiser failure: a lower length-scale bound of 0.01 still ends at its bound with the same noise (576 deg/h).
With the table's rate as input the GP's noise level comes out at the recording's (14.3 deg/h against the 14.1
drawn at 2 Hz). gyrosid meets the same problem by its own means (the level-spacing width bound).
The GP's hyper-parameters are the best of 1 + 2 random restarts of the marginal-likelihood optimiser
(scikit-learn's n_restarts_optimizer); its convergence warnings are kept in the output.

    peers.py --train rec.csv --eval grid.csv [--eval heldout.csv ...] --out peers.json [--gp-subset 2000]

For each evaluation recording it writes the rms and 95 % coverage (GP: its own predictive sigma) of
predicted - true error, with the fit time.
"""
import argparse
import json
import os
import sys
import time
import warnings

import numpy as np
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel
from sklearn.kernel_ridge import KernelRidge
from sklearn.model_selection import GridSearchCV, KFold

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import rate_error_dph, read_recording  # noqa: E402


def inputs_and_error(path, rate="gyro_dps"):
    """(rate, temperature) inputs and the rate error (deg/h) of a recording; rate: the column used as input
    (gyro_dps, the measured rate, to evaluate; ref_rate_dps, the table's rate, to train - see above)."""
    _, c = read_recording(path)
    return np.column_stack([c[rate], c["temp_c"]]), rate_error_dph(c)


def fit_krr(x, y, subset, rng):
    """KernelRidge on a random subset, alpha and gamma by 3-fold CV over a log grid (the tuned peer)."""
    idx = rng.choice(len(x), size=min(subset, len(x)), replace=False)
    grid = {"alpha": [1e-3, 1e-2, 1e-1, 1.0, 10.0], "gamma": [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0]}
    search = GridSearchCV(KernelRidge(kernel="rbf"), grid, cv=KFold(3, shuffle=True, random_state=0),
                          scoring="neg_mean_squared_error", n_jobs=1)
    search.fit(x[idx], y[idx])
    return search.best_estimator_, {"alpha": search.best_params_["alpha"], "gamma": search.best_params_["gamma"],
                                    "samples_used": int(len(idx))}


def fit_gp(x, y, subset, rng, restarts=2):
    """GP with an anisotropic RBF plus white noise on a random subset; hyper-parameters by the marginal
    likelihood, best of 1 + `restarts` starts (the extra starts drawn log-uniformly within the bounds)."""
    idx = rng.choice(len(x), size=min(subset, len(x)), replace=False)
    kernel = ConstantKernel(1.0, (1e-3, 1e3)) * RBF(length_scale=[0.3, 0.5], length_scale_bounds=(1e-3, 1e2)) + \
        WhiteKernel(0.1, (1e-8, 1e1))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        gp = GaussianProcessRegressor(kernel=kernel, normalize_y=True, n_restarts_optimizer=restarts,
                                      random_state=0).fit(x[idx], y[idx])
    return gp, {"kernel": str(gp.kernel_), "log_marginal_likelihood": float(gp.log_marginal_likelihood_value_),
                "restarts": restarts, "warnings": sorted({str(w.message)[:200] for w in caught}),
                "samples_used": int(len(idx))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--train", required=True)
    ap.add_argument("--eval", action="append", required=True, help="recording to score (repeatable)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--gp-subset", type=int, default=2000)
    ap.add_argument("--krr-subset", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--gp-restarts", type=int, default=2)
    a = ap.parse_args()
    x, y = inputs_and_error(a.train, rate="ref_rate_dps")
    lo, hi = x.min(axis=0), x.max(axis=0)
    norm = lambda v: 2.0 * (v - lo) / (hi - lo) - 1.0  # noqa: E731
    rng = np.random.default_rng(a.seed)
    evals = [(p,) + inputs_and_error(p) for p in a.eval]
    out = {}
    for name in ("krr", "gp"):
        start = time.time()
        if name == "krr":
            model, info = fit_krr(norm(x), y, a.krr_subset, rng)
        else:
            model, info = fit_gp(norm(x), y, a.gp_subset, rng, a.gp_restarts)
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
