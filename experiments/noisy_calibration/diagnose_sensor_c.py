#!/usr/bin/env python3
"""Sensor C diagnosis (issue 11, fifth run): is the hybrid's distance from the Cramer-Rao floor bias or variance,
and which of the law's shapes (generator_c.py) does the floor know that the hybrid does not?

    diagnose_sensor_c.py fits --gyrosid build/gyrosid --out /tmp/diag [--programme staircase] [--seeds 1,2,3,4]
        gyrosid's hybrid and bayes on a noise-free recording and at white 1 / 10 deg/h (seed 1), and the hybrid
        at white 1 over --seeds: held-out rms, 95 % band coverage, rms sigma, the error between the staircase's
        rate levels, and bias^2 / variance over the seeds (bias^2 = mean over points of the seeds' mean error
        squared, less variance / seeds).
    diagnose_sensor_c.py shapes --out /tmp/diag [--programme sine_sweep] [--white 1]
        a numpy re-implementation of the hybrid (the same physics columns, 200 Gaussian nodes at a
        farthest-point subset, widths on a grid, prior and noise precision by MacKay's fixed point) with the
        law's own shapes added to the flat-prior columns: held-out rms against the floor.
"""
import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, HERE)
import generator_c  # noqa: E402
from gyrosid_experiments import read_recording  # noqa: E402

METHODS = {"hybrid": ["--model", "hybrid", "--set", "noise=auto"], "bayes": ["--solver", "bayes"]}
LEVELS = np.linspace(-150, 150, 13)  # the staircase's rate levels


def recording(out, programme, white, seed, noise_free=False):
    path = os.path.join(out, "%s_%s_s%d.csv" % (programme, "free" if noise_free else "w%g" % white, seed))
    if not os.path.exists(path):
        generator_c.generate(path, programme, white if white > 0 else 1.0, seed=seed, noise_free=noise_free)
    return path


def heldout(out):
    path = os.path.join(out, "heldout.csv")
    if not os.path.exists(path):
        generator_c.generate(path, "heldout", 0.0, seed=999, noise_free=True)
    return path


def fitted_errors(gyrosid, rec, method, held):
    model = rec[:-4] + "_%s.json" % method
    if not os.path.exists(model):
        subprocess.run([gyrosid, "calibrate", "--recording", rec] + METHODS[method] + ["--out", model], check=True, stdout=subprocess.DEVNULL)
    comp = model[:-5] + "_held.csv"
    if not os.path.exists(comp):
        subprocess.run([gyrosid, "compensate", "--model", model, "--recording", held, "--out", comp], check=True, stdout=subprocess.DEVNULL)
    _, c = read_recording(comp)
    return (c["compensated_dps"] - c["ref_rate_dps"]) * 3600.0, c["compensated_sigma_dps"] * 3600.0, c["ref_rate_dps"]


def fits(a):
    held = heldout(a.out)
    for label, white, free in (("noise-free", 0.0, True), ("white 1", 1.0, False), ("white 10", 10.0, False)):
        for method in METHODS:
            e, s, w = fitted_errors(a.gyrosid, recording(a.out, a.programme, white, 1, free), method, held)
            between = np.min(np.abs(w[:, None] - LEVELS[None, :]), axis=1) > 7.5
            print("%s %-10s %-6s held-out rms %.3f  coverage %.3f  rms sigma %.3f  (staircase: |rate - level| > 7.5 deg/s: rms %.3f)" % (
                a.programme, label, method, np.sqrt(np.mean(e * e)), np.mean(np.abs(e) <= 1.96 * s), np.sqrt(np.mean(s * s)),
                np.sqrt(np.mean(e[between] ** 2))))
    seeds = [int(v) for v in a.seeds.split(",")]
    errors = np.array([fitted_errors(a.gyrosid, recording(a.out, a.programme, 1.0, k), "hybrid", held)[0] for k in seeds])
    var = np.mean(errors.var(axis=0, ddof=1))
    print("%s white 1, hybrid over seeds %s: mse %.4f = bias^2 %.4f + variance %.4f (deg/h)^2" % (
        a.programme, a.seeds, np.mean(errors ** 2), np.mean(errors.mean(axis=0) ** 2) - var / len(seeds), var))


def shapes(a):
    np.seterr(all="ignore")  # the fixed point overflows harmlessly at grid points far from the optimum
    _, r = read_recording(recording(a.out, a.programme, a.white, 1))
    _, h = read_recording(heldout(a.out))

    def inputs(c):
        return np.column_stack([(c["temp_c"] - 22.5) / 62.5, c["ref_rate_dps"] / 150.0])

    def fixed(c, extra):
        t, u = (c["temp_c"] - 22.5) / 62.5, c["ref_rate_dps"] / 150.0
        g = generator_c.columns(c["ref_rate_dps"], c["temp_c"])
        cols = [t ** i for i in range(4)] + [u * t ** i * u ** j for i in range(3) for j in range(4)]  # the hybrid's physics
        cols += [g[:, generator_c.NAMES.index(n)] for n in extra]
        return np.column_stack(cols)

    x, y, xh = inputs(r), (r["gyro_dps"] - r["ref_rate_dps"]) * 3600.0, inputs(h)
    yh = generator_c.error_dph(h["ref_rate_dps"], h["temp_c"])
    idx, d = [0], np.sum((x - x[0]) ** 2, 1)
    for _ in range(199):
        idx.append(int(np.argmax(d)))
        d = np.minimum(d, np.sum((x - x[idx[-1]]) ** 2, 1))
    centres = x[idx]

    def phi(z, widths):
        return np.exp(-0.5 * np.sum(((z[:, None, :] - centres[None]) / widths) ** 2, 2))

    cov = generator_c.crb(r["t_s"], r["ref_rate_dps"], r["temp_c"], a.white)
    floor = np.sqrt(np.mean(generator_c.floor_sigma(cov, h["ref_rate_dps"], h["temp_c"]) ** 2))
    for extra in ([], ["sf_ripple"], ["bias_tanh", "bias_bump"], ["sf_u3"], ["sf_ripple", "bias_tanh", "bias_bump", "sf_u3"]):
        f, fh = fixed(r, extra), fixed(h, extra)
        q, _ = np.linalg.qr(f / np.linalg.norm(f, axis=0))
        best = None
        for wr in (0.08, 0.12, 0.16, 0.24, 0.35):
            for wt in (0.3, 0.6, 1.2):
                p = phi(x, np.array([wt, wr]))
                pp, yp = p - q @ (q.T @ p), y - q @ (q.T @ y)
                lam, v = np.linalg.eigh(pp.T @ pp)
                lam, bt = np.maximum(lam, 0.0), v.T @ (pp.T @ yp)
                n, al, be = len(y) - f.shape[1], 1.0, 1.0 / np.var(yp)
                for _ in range(200):  # MacKay's fixed point
                    m = be * bt / (al + be * lam)
                    g = np.sum(be * lam / (al + be * lam))
                    ed = yp @ yp - 2 * m @ bt + np.sum(lam * m * m)
                    al, be = g / (m @ m), (n - g) / ed
                m = be * bt / (al + be * lam)
                ed = yp @ yp - 2 * m @ bt + np.sum(lam * m * m)
                le = 0.5 * (200 * np.log(al) + n * np.log(be) - be * ed - al * m @ m - np.sum(np.log(al + be * lam)))
                if best is None or le > best[0]:
                    best = (le, np.array([wt, wr]), al, be, g)
        le, widths, al, be, g = best
        hm = np.hstack([phi(x, widths), f])
        prec = be * hm.T @ hm
        prec[np.arange(200), np.arange(200)] += al
        prec[200:, 200:] += 1e-10 * np.eye(f.shape[1])
        w = np.linalg.solve(prec, be * hm.T @ y)
        hh = np.hstack([phi(xh, widths), fh])
        e = hh @ w - yh
        s = np.sqrt(np.sum(np.linalg.solve(np.linalg.cholesky(prec), hh.T) ** 2, 0))
        print("%s white %g, physics + %-40s widths (T, rate) %.2f, %.2f, RBF parameters %.1f: held-out rms %.3f (floor %.3f, %.2fx), coverage %.3f" % (
            a.programme, a.white, ", ".join(extra) or "nothing", widths[0], widths[1], g, np.sqrt(np.mean(e * e)), floor,
            np.sqrt(np.mean(e * e)) / floor, np.mean(np.abs(e) <= 1.96 * s)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["fits", "shapes"])
    ap.add_argument("--gyrosid", default=os.path.join(HERE, "..", "..", "build", "gyrosid"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--programme", default="staircase")
    ap.add_argument("--white", type=float, default=1.0)
    ap.add_argument("--seeds", default="1,2,3,4")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    fits(a) if a.what == "fits" else shapes(a)


if __name__ == "__main__":
    main()
