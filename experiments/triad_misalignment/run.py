#!/usr/bin/python3
"""Triad misalignment (issue 10): gyrosid's joint estimate of a triad's misalignment/scale-factor matrix M,
biases and per-gyro surfaces - its statistics, joint against sequential, triads from an independent
generator, and real sessions against imucal's own result.

    experiments/triad_misalignment/run.py [mc|compare|independent|real|all] [--gyrosid build/gyrosid]
                                          [--out experiments/triad_misalignment/results] [--jobs 2] [--force]

Each part writes results/<part>.md (+ .csv); intermediates (recordings, models) stay under results/data/
and results/models/ and are reused on a rerun. See README.md for what each part answers.
"""
import argparse
import concurrent.futures
import math
import os
import sys

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
from gyrosid_experiments import Runner, add_gyrosid_argument, fmt, load_json, markdown_table, write_csv, write_text  # noqa: E402

AXES = "xyz"
OFF = [(i, j) for i in range(3) for j in range(3) if i != j]


def first_order_m(angles_mrad):
    """Eq 3.72 from the config's angles (mrad): M_ij = +-(IA angle + insertion angle), first order, rad."""
    s = {a: (np.array(v["ia"]) + np.array(v["insertion"])) * 1e-3 for a, v in angles_mrad.items()}
    m = np.zeros((3, 3))
    m[0, 1], m[0, 2] = s["x"][1], -s["x"][0]
    m[1, 0], m[1, 2] = -s["y"][0], s["y"][1]
    m[2, 0], m[2, 1] = s["z"][1], -s["z"][0]
    return m, s


def matrix(j, key="matrix"):
    return np.array([[np.nan if v is None else v for v in row] for row in j["misalignment"][key]], dtype=float)


class Experiment:
    def __init__(self, args):
        self.cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))
        self.run = Runner(args.gyrosid, args.out, args.force)
        self.jobs = args.jobs
        self.out = args.out

    def sensor(self, path):
        return path if path.startswith("builtin:") else os.path.join(HERE, path)

    def simulate_and_fit(self, sensor, trajectory, seed, calibrate, tag):
        rec = self.run.path("data", tag, "seed%d.csv" % seed)
        args = ["simulate", "--sensor", self.sensor(sensor), "--trajectory", trajectory, "--seed", seed, "--out", rec]
        if seed == 0:
            args.insert(1, "--noise-free")
        self.run.run(args, rec)
        model = self.run.path("models", tag, "seed%d.json" % seed)
        self.run.run(["calibrate", "--model", "triad", "--recording", rec] + calibrate + ["--out", model], model)
        return load_json(model)

    def parallel(self, fn, items):
        with concurrent.futures.ThreadPoolExecutor(self.jobs) as pool:
            return list(pool.map(fn, items))

    # --- Monte Carlo ---------------------------------------------------------------------------------
    def monte_carlo(self):
        c = self.cfg["monte_carlo"]
        sensor_cfg = yaml.safe_load(open(self.sensor(c["sensor"])))
        m1, sums = first_order_m(sensor_cfg["misalignment_mrad"])
        planted = m1.copy()
        s10 = c["planted"]["scale_factor_at_10dps_ppm"] * 1e-6
        for i, a in enumerate(AXES):  # exact diagonal: (1 + s) cos-product - 1, to second order in the angles
            planted[i, i] = (1 + s10) * (1 - 0.5 * float(sums[a] @ sums[a])) - 1
        noise_free = self.simulate_and_fit(c["sensor"], c["trajectory"], 0, c["calibrate"], "mc")
        seeds = list(range(c["first_seed"], c["first_seed"] + c["runs"]))
        fits = self.parallel(lambda s: self.simulate_and_fit(c["sensor"], c["trajectory"], s, c["calibrate"], "mc"), seeds)
        est = np.array([matrix(f) for f in fits])
        sig = np.array([matrix(f, "sigma") for f in fits])
        t0 = np.array([f["bias_dph"]["temperature_c"] for f in fits])
        b_est = np.array([f["bias_dph"]["value"] for f in fits])
        b_sig = np.array([f["bias_dph"]["sigma"] for f in fits])
        pb = c["planted"]
        b_true = np.array([[pb["bias_dph"][a] + pb["bias_temperature_dph"][a][0] * (t - 25) + pb["bias_temperature_dph"][a][1] * (t - 25) ** 2
                            for a in range(3)] for t in t0])
        # The noise floor of an off-diagonal entry (Cramer-Rao for white noise, bias known): two turns of T s
        # at rate w about its column's axis on each of P plateaus, N the white-noise density.
        n_density = math.radians(10.0 / 3600.0)  # 10 deg/h at 1 Hz, rad/s/sqrt(Hz)
        floor = n_density / (math.radians(10.0) * math.sqrt(2 * 180.0 * 3))
        rows = []
        for (i, j) in [(i, j) for i in range(3) for j in range(3)]:
            e, s, p = est[:, i, j], sig[:, i, j], planted[i, j]
            z = (e - p) / s
            rows.append({"entry": "M_%s%s" % (AXES[i], AXES[j]), "unit": "urad" if i != j else "ppm", "planted": p * 1e6,
                         "noise_free": matrix(noise_free)[i, j] * 1e6, "bias": (e.mean() - p) * 1e6,
                         "bias_in_sigma": (e.mean() - p) / (e.std(ddof=1) / math.sqrt(len(e))),
                         "sigma_mc": e.std(ddof=1) * 1e6, "sigma_reported": s.mean() * 1e6, "floor": floor * 1e6 if i != j else "",
                         "cover_1sigma": float(np.mean(np.abs(z) <= 1)), "inside_3sigma": float(np.mean(np.abs(z) <= 3))})
        for a in range(3):
            e, s, p = b_est[:, a], b_sig[:, a], b_true[:, a]
            z = (e - p) / s
            rows.append({"entry": "b_%s(T0)" % AXES[a], "unit": "deg/h", "planted": p.mean(), "noise_free": noise_free["bias_dph"]["value"][a],
                         "bias": (e - p).mean(), "bias_in_sigma": (e - p).mean() / ((e - p).std(ddof=1) / math.sqrt(len(e))),
                         "sigma_mc": (e - p).std(ddof=1), "sigma_reported": s.mean(), "floor": "",
                         "cover_1sigma": float(np.mean(np.abs(z) <= 1)), "inside_3sigma": float(np.mean(np.abs(z) <= 3))})
        z_off = np.array([(est[:, i, j] - planted[i, j]) / sig[:, i, j] for (i, j) in OFF]).T
        runs_all_inside = float(np.mean(np.all(np.abs(z_off) <= 3, axis=1)))
        cols = ["entry", "unit", "planted", "noise_free", "bias", "bias_in_sigma", "sigma_mc", "sigma_reported", "floor", "cover_1sigma", "inside_3sigma"]
        write_csv(os.path.join(self.out, "monte_carlo.csv"), rows, cols)
        off = [r for r in rows if r["unit"] == "urad"]
        text = "# Monte Carlo: %d simulated triads, six positions + 10 deg/s turns, 10 deg/h white noise\n\n" % len(fits)
        text += ("Sensor `%s`, trajectory `%s`, fit `gyrosid calibrate --model triad %s`. Planted M: eq 3.72 from the "
                 "config's angles (off-diagonal, first order; the exact chain differs by < 1e-9), diagonal (1 + s(10 deg/s)) "
                 "times the cosine product, minus 1. Bias: the config's polynomial at the fit's reference temperature.\n\n"
                 % (c["sensor"], c["trajectory"], " ".join(c["calibrate"])))
        text += markdown_table(rows, cols, ["entry", "unit", "planted", "noise-free fit", "bias", "bias / (sd/sqrt(n))", "sigma (MC)",
                                            "sigma (reported)", "floor", "1-sigma coverage", "inside 3 sigma"])
        text += ("\nOff-diagonal: reported sigma %s..%s urad (floor %s urad), MC sigma %s..%s urad; 1-sigma coverage %s..%s "
                 "(pooled %s); inside 3 sigma per entry %s..%s (pooled %s); runs with all six inside 3 sigma: %s.\n"
                 % (fmt(min(r["sigma_reported"] for r in off)), fmt(max(r["sigma_reported"] for r in off)), fmt(floor * 1e6),
                    fmt(min(r["sigma_mc"] for r in off)), fmt(max(r["sigma_mc"] for r in off)),
                    fmt(min(r["cover_1sigma"] for r in off)), fmt(max(r["cover_1sigma"] for r in off)),
                    fmt(float(np.mean(np.abs(z_off) <= 1))), fmt(min(r["inside_3sigma"] for r in off), 4),
                    fmt(max(r["inside_3sigma"] for r in off), 4), fmt(float(np.mean(np.abs(z_off) <= 3)), 4), fmt(runs_all_inside, 4)))
        write_text(os.path.join(self.out, "monte_carlo.md"), text)
        print(text)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("part", nargs="?", default="all", choices=["mc", "compare", "independent", "real", "all"])
    add_gyrosid_argument(p)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--force", action="store_true")
    args = p.parse_args()
    e = Experiment(args)
    parts = {"mc": e.monte_carlo}
    for name, fn in parts.items():
        if args.part in (name, "all"):
            fn()


if __name__ == "__main__":
    main()
