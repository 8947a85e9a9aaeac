#!/usr/bin/python3
"""Triad misalignment (issue 10): gyrosid's joint estimate of a triad's misalignment/scale-factor matrix M,
biases and per-gyro surfaces - its statistics, joint against sequential, triads from an independent
generator, and real sessions against imucal's own result.

    experiments/triad_misalignment/run.py [mc|compare|more|auto|independent|real|summary|all] [--gyrosid build/gyrosid]
                                          [--out experiments/triad_misalignment/results] [--jobs 2] [--force]
                                          [--kinds rbf] [--seeds N] [--cells training/sensor/kind,...]

Each part writes results/<part>.md (+ .csv); intermediates (recordings, models) stay under results/data/
and results/models/ and are reused on a rerun. See README.md for what each part answers.
"""
import argparse
import csv
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


PAIRED_COLUMNS = ["training", "sensor", "surfaces", "quantity", "noise_free_ratio", "median_joint", "median_seq", "median_ratio", "ratio_ci95",
                  "joint_wins", "sign_p"]


def fit_bic(fit):
    """The fit's BIC as gyrosid writes it (summary.details.information_criterion; definition in
    solvers/triad/triad_fit.h, the same number surface.sf_cross_order=auto compares); "" where gyrosid leaves it
    null (sequential rbf surfaces: their parameters are not counted)."""
    ic = fit["summary"]["details"].get("information_criterion", {})
    return "" if ic.get("bic") is None else ic["bic"]


def surface_order(fit, key):
    """The classical surfaces' order `key` (sf_rate_order, sf_cross_order) the fit used (auto: the one
    order_criterion chose), "" for other surfaces."""
    return fit["summary"]["details"].get("surface_" + key, "")


def sign_test_p(wins, n):
    """Two-sided sign test: P(a split at least as uneven as wins/n) under a fair coin."""
    k = min(wins, n - wins)
    return min(1.0, 2.0 * sum(math.comb(n, i) for i in range(k + 1)) / 2.0 ** n)


def paired_summary(rows, flights, seeds, first="joint", second="sequential"):
    """Per training, sensor, surface kind and quantity: `first` (joint) against `second` (sequential) estimation,
    paired by seed; the columns keep the names joint / seq."""
    out = []
    val = lambda r, k: float(r[k])
    groups = sorted({(r["training"], r["sensor"], r["surfaces"]) for r in rows})
    for train, sensor, kind in groups:
        pick = lambda est: {int(r["seed"]): r for r in rows if (r["training"], r["sensor"], r["surfaces"], r["estimation"]) == (train, sensor, kind, est)}
        j, q = pick(first), pick(second)
        noisy = [s for s in seeds if s in j and s in q]
        if not noisy:
            continue
        for key in ["offdiag_rms_err_urad", "train_rms_dph"] + [f + "_m" for f in flights]:
            a, b = np.array([val(j[s], key) for s in noisy]), np.array([val(q[s], key) for s in noisy])
            ratio = a / b
            rng = np.random.default_rng(12345)
            boot = np.median(rng.choice(ratio, (4000, len(ratio))), axis=1)
            wins = int(np.sum(a <= b * (1 + 1e-9)))
            out.append({"training": train, "sensor": sensor, "surfaces": kind, "quantity": key,
                        "noise_free_ratio": val(j[0], key) / val(q[0], key) if 0 in j and 0 in q else "",
                        "median_joint": float(np.median(a)), "median_seq": float(np.median(b)), "median_ratio": float(np.median(ratio)),
                        "ratio_ci95": "%s..%s" % (fmt(float(np.percentile(boot, 2.5)), 5), fmt(float(np.percentile(boot, 97.5)), 5)),
                        "ci_lo": float(np.percentile(boot, 2.5)), "ci_hi": float(np.percentile(boot, 97.5)),
                        "joint_wins": "%d/%d" % (wins, len(noisy)), "sign_p": sign_test_p(wins, len(noisy))})
    return out


def interval_word(g):
    """A paired_summary row's verdict by its 95 % interval: better / worse when it lies below / above 1, else tie."""
    return "better" if g["ci_hi"] < 1 else "worse" if g["ci_lo"] > 1 else "tie"


def chosen_by_cell(rows):
    """Per (training, sensor, surfaces): the fit estimation=auto returned on each noisy seed."""
    chosen = {}
    for r in rows:
        if int(r["seed"]) > 0:
            chosen.setdefault((r["training"], r["sensor"], r["surfaces"]), []).append(r["chosen"])
    return chosen


def comparative_target_lines(who, label, groups, medians, flights):
    """The comparative targets' lines for one set of cells: `groups` maps (training, sensor, surfaces) to each flight's
    interval verdict (better / worse / tie against sequential), `medians` to its median paired ratio."""
    verdict = lambda ok: "met" if ok else "missed"
    worse = ["%s/%s/%s %s" % (k + (f,)) for k, v in sorted(groups.items()) for f, w in zip(flights, v) if w == "worse"]
    above = ["%s/%s/%s %s %s" % (k + (f, fmt(m, 6))) for k, v in sorted(groups.items()) for f, m in zip(flights, medians[k]) if m > 1]
    nonlinear = {k: v for k, v in groups.items() if k[1] == "rate_nonlinear"}
    not_better = ["%s/%s %s %s" % (k[0], k[2], f, w) for k, v in sorted(nonlinear.items()) for f, w in zip(flights, v) if w != "better"]
    not_below = ["%s/%s %s %s" % (k[0], k[2], f, fmt(m, 6)) for k, v in sorted(nonlinear.items()) for f, m in zip(flights, medians[k]) if not m < 1]
    return ["* %s at least as good as sequential on every flight, %s:" % (who, label),
            "  interval criterion (no flight's interval above 1): %s - %s;" % ("; ".join(worse) or "no flight worse", verdict(not worse)),
            "  literal criterion (every median ratio <= 1): %s - %s." % ("; ".join(above) or "none above 1", verdict(not above)),
            "* Strictly better when rate-nonlinear, %s:" % label,
            "  interval criterion (every flight's interval below 1): not better: %s - %s;" % ("; ".join(not_better) or "none", verdict(not not_better)),
            "  literal criterion (every median ratio < 1): not below 1: %s - %s." % ("; ".join(not_below) or "none", verdict(not not_below))]


class Experiment:
    def __init__(self, args):
        self.cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))
        self.run = Runner(args.gyrosid, args.out, args.force)
        self.jobs = args.jobs
        self.out = args.out
        self.kinds = args.kinds.split(",") if getattr(args, "kinds", None) else []
        self.seeds = getattr(args, "seeds", 0)
        self.cells = getattr(args, "cells", "")
        self.estimation = getattr(args, "estimation", "")

    def sensor(self, path):
        return path if path.startswith("builtin:") else os.path.join(HERE, path)

    def simulate_and_fit(self, sensor, trajectory, seed, calibrate, tag):
        return self.simulate_and_fit_tagged(sensor, trajectory, seed, calibrate, tag, tag)

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
        # --estimation: the same recordings fitted in that mode, written to monte_carlo_<mode>.md (default: the
        # config's arguments - the CLI's default, joint - to monte_carlo.md).
        calibrate = c["calibrate"] + (["--" + self.estimation] if self.estimation else [])
        name = "monte_carlo" + ("_" + self.estimation if self.estimation else "")
        tag = "mc" + ("_" + self.estimation if self.estimation else "")
        fit = lambda s: self.simulate_and_fit_tagged(c["sensor"], c["trajectory"], s, calibrate, tag, "mc")
        noise_free = fit(0)
        seeds = list(range(c["first_seed"], c["first_seed"] + c["runs"]))
        fits = self.parallel(fit, seeds)
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
        write_csv(os.path.join(self.out, name + ".csv"), rows, cols)
        off = [r for r in rows if r["unit"] == "urad"]
        text = "# Monte Carlo: %d simulated triads, six positions + 10 deg/s turns, 10 deg/h white noise\n\n" % len(fits)
        text += ("Sensor `%s`, trajectory `%s`, fit `gyrosid calibrate --model triad %s`. Planted M: eq 3.72 from the "
                 "config's angles (off-diagonal, first order; the exact chain differs by < 1e-9), diagonal (1 + s(10 deg/s)) "
                 "times the cosine product, minus 1. Bias: the config's polynomial at the fit's reference temperature.\n\n"
                 % (c["sensor"], c["trajectory"], " ".join(calibrate)))
        text += markdown_table(rows, cols, ["entry", "unit", "planted", "noise-free fit", "bias", "bias / (sd/sqrt(n))", "sigma (MC)",
                                            "sigma (reported)", "floor", "1-sigma coverage", "inside 3 sigma"])
        text += ("\nOff-diagonal: reported sigma %s..%s urad (floor %s urad), MC sigma %s..%s urad; 1-sigma coverage %s..%s "
                 "(pooled %s); inside 3 sigma per entry %s..%s (pooled %s); runs with all six inside 3 sigma: %s.\n"
                 % (fmt(min(r["sigma_reported"] for r in off)), fmt(max(r["sigma_reported"] for r in off)), fmt(floor * 1e6),
                    fmt(min(r["sigma_mc"] for r in off)), fmt(max(r["sigma_mc"] for r in off)),
                    fmt(min(r["cover_1sigma"] for r in off)), fmt(max(r["cover_1sigma"] for r in off)),
                    fmt(float(np.mean(np.abs(z_off) <= 1))), fmt(min(r["inside_3sigma"] for r in off), 4),
                    fmt(max(r["inside_3sigma"] for r in off), 4), fmt(float(np.mean(np.abs(z_off) <= 3)), 4), fmt(runs_all_inside, 4)))
        chosen = [f["summary"]["details"].get("estimation_chosen") for f in fits]
        if self.estimation == "auto":
            text += "\nestimation=auto returned the joint fit in %d of %d runs, the sequential in the others.\n" % (chosen.count("joint"), len(fits))
        write_text(os.path.join(self.out, name + ".md"), text)
        print(text)


    # --- joint against sequential ---------------------------------------------------------------------
    def cof(self, model, sensor, flight):
        out = self.run.path("cof", os.path.relpath(model, self.run.path("models")).replace("/", "_")[:-5] + "_" + flight, "cof.json")
        self.run.run(["cof", "--model", model, "--sensor", self.sensor(sensor), "--trajectory", flight,
                      "--rate-hz", self.cfg["compare"]["cof_rate_hz"], "--out", os.path.dirname(out)], out)
        j = load_json(out)
        return j["error_after_1h_m"] if j.get("error_after_1h_m") is not None else j["end_error_m"]

    def compare(self):
        c = self.cfg["compare"]
        trainings = c["trainings"]
        jobs = [(train, sname, kind, est, seed) for train in trainings for sname in c["sensors"]
                for kind in trainings[train]["kinds"] if not self.kinds or kind in self.kinds
                for est in ("joint", "sequential") for seed in [0] + c["seeds"][:self.seeds or None]]

        rows = self.parallel(self.compare_row, jobs)
        if self.kinds:  # the other surface kinds' rows kept from the last full run
            import csv
            keep = [r for r in csv.DictReader(open(os.path.join(self.out, "compare.csv"))) if r["surfaces"] not in self.kinds]
            for r in keep:
                r.setdefault("training", "rate_sweep")
                for k in r:
                    if k not in ("training", "sensor", "surfaces", "estimation", "rate_order", "cross_order"):
                        r[k] = int(r[k]) if k == "seed" else float(r[k]) if r[k] not in ("", None) else ""  # bic: none for rbf rows
            rows = keep + rows
        cols = ["training", "sensor", "surfaces", "estimation", "seed", "offdiag_rms_err_urad", "train_rms_dph"] + [f + "_m" for f in c["flights"]]
        write_csv(os.path.join(self.out, "compare.csv"), rows, cols + ["bic", "rate_order", "cross_order", "time_s"])
        text = "# Joint against sequential estimation\n\nTraining trajectories: %s. Criterion of fit (end error; long flight after 1 h; noise-free flights) on %s. " \
               "Per group: the noise-free fit (seed 0), then the noisy seeds (10 deg/h; how many: joint_wins' denominator) paired by seed: median of " \
               "joint/sequential with a 95 %% bootstrap interval of that median, runs where joint <= sequential, and the two-sided sign-test p of " \
               "those wins.\n\n" % (", ".join("%s `%s`" % (k, v["trajectory"]) for k, v in trainings.items()), ", ".join(c["flights"]))
        table = [dict(g, **{k: fmt(g[k], 5) for k in ("noise_free_ratio", "median_ratio") if g[k] != ""}) for g in paired_summary(rows, c["flights"], c["seeds"])]
        text += markdown_table(table, PAIRED_COLUMNS)
        write_text(os.path.join(self.out, "compare.md"), text)
        print(text)

    def more(self):
        """More paired seeds for chosen compare cells (--cells training/sensor/kind,...; --seeds N: seeds 1..N, the
        compare's 20 included and reused): is a cell's joint/sequential offset real or a draw of 20 seeds?"""
        cells = [tuple(x.split("/")) for x in self.cells.split(",") if x]
        seeds = list(range(1, (self.seeds or 60) + 1))
        jobs = [(t, sn, k, est, seed) for (t, sn, k) in cells for est in ("joint", "sequential") for seed in [0] + seeds]
        rows = self.parallel(self.compare_row, jobs)
        flights = self.cfg["compare"]["flights"]
        cols = ["training", "sensor", "surfaces", "estimation", "seed", "offdiag_rms_err_urad", "train_rms_dph"] + [f + "_m" for f in flights]
        write_csv(os.path.join(self.out, "compare_more.csv"), rows, cols + ["bic", "rate_order", "cross_order", "time_s"])
        out = []
        for g in paired_summary(rows, flights, seeds):
            if not g["quantity"].endswith("_m") and g["quantity"] != "offdiag_rms_err_urad":
                continue
            pick = lambda est: {int(r["seed"]): float(r[g["quantity"]]) for r in rows if (r["training"], r["sensor"], r["surfaces"], r["estimation"]) ==
                                (g["training"], g["sensor"], g["surfaces"], est) and int(r["seed"]) > 0}
            j, q = pick("joint"), pick("sequential")
            d = np.array([j[s] - q[s] for s in seeds])
            g = dict(g, mean_diff=float(d.mean()), diff_se=float(d.std(ddof=1) / math.sqrt(len(d))), t=float(d.mean() / (d.std(ddof=1) / math.sqrt(len(d)))),
                     seq_sd=float(np.std([q[s] for s in seeds], ddof=1)))
            out.append(g)
        cols = ["training", "sensor", "surfaces", "quantity", "noise_free_ratio", "median_ratio", "ratio_ci95", "joint_wins", "sign_p", "mean_diff", "diff_se", "t", "seq_sd"]
        text = ("# More paired seeds for chosen cells\n\n`run.py more --cells %s --seeds %d`: seeds 1..%d (the compare's 20 and more), joint against "
                "sequential paired by seed. median_ratio [95 %% bootstrap interval of the median], joint wins, sign-test p; mean_diff = mean of "
                "joint - sequential (m for flights, urad for the off-diagonals) with its standard error and t; seq_sd = the sequential criterion's "
                "seed-to-seed standard deviation.\n\n" % (self.cells, len(seeds), len(seeds)))
        text += markdown_table([dict(g, **{k: fmt(g[k], 5) for k in ("noise_free_ratio", "median_ratio")}) for g in out], cols)
        write_text(os.path.join(self.out, "compare_more.md"), text)
        print(text)

    def auto(self):
        """estimation=auto (--auto: both fits, the joint kept where a test on M rejects the sequential fit's restriction,
        solvers/triad/auto_estimation.h) on every training and sensor, for the CLI's default surfaces (--kinds, default
        classical,rbf): against the compare's sequential and joint rows of the same recordings, paired by seed."""
        c = self.cfg["compare"]
        kinds = self.kinds or ["classical", "rbf"]
        seeds = c["seeds"][:self.seeds or None]
        jobs = [(train, sname, kind, "auto", seed) for train in c["trainings"] for sname in c["sensors"]
                for kind in kinds if kind in c["trainings"][train]["kinds"] for seed in [0] + seeds]
        rows = self.parallel(self.compare_row, jobs)
        flights = c["flights"]
        cols = ["training", "sensor", "surfaces", "estimation", "chosen", "seed", "offdiag_rms_err_urad", "train_rms_dph"] + [f + "_m" for f in flights]
        write_csv(os.path.join(self.out, "compare_auto.csv"), rows, cols + ["time_s"])
        both = rows + [r for r in csv.DictReader(open(os.path.join(self.out, "compare.csv"))) if r["surfaces"] in kinds]
        chosen = chosen_by_cell(rows)
        text = ("# estimation=auto against sequential and joint\n\n`run.py auto`: the CLI's `--auto` (solvers/triad/auto_estimation.h) on the "
                "compare's recordings, %d noisy seeds; columns as in compare.md, with auto in the place of joint. Fits that returned the joint "
                "one, per cell: %s.\n\n" % (len(seeds), "; ".join("%s/%s/%s %d of %d" % (k + (v.count("joint"), len(v))) for k, v in sorted(chosen.items()))))
        for second in ("sequential", "joint"):
            table = [dict(g, **{k: fmt(g[k], 5) for k in ("noise_free_ratio", "median_ratio") if g[k] != ""})
                     for g in paired_summary(both, flights, seeds, "auto", second) if g["quantity"] != "train_rms_dph"]
            text += "## auto against %s\n\n" % second + markdown_table(table, PAIRED_COLUMNS) + "\n"
        write_text(os.path.join(self.out, "compare_auto.md"), text)
        print(text)

    def compare_row(self, job):
        """One fit of the compare (training, sensor, surface kind, estimation, seed) and its flights' criterion of fit."""
        c = self.cfg["compare"]
        trainings = c["trainings"]
        train, sname, kind, est, seed = job
        sensor = c["sensors"][sname]
        sensor_cfg = yaml.safe_load(open(self.sensor(sensor))) if not sensor.startswith("builtin:") else \
            yaml.safe_load(open(os.path.join(HERE, "..", "..", "configs", sensor[len("builtin:"):])))
        planted, _ = first_order_m(sensor_cfg["misalignment_mrad"])
        folder = "compare" if train == "rate_sweep" else "compare_" + train  # rate_sweep: the original paths
        tag = "%s/%s_%s_%s" % (folder, sname, kind, est)
        fit = self.simulate_and_fit_tagged(sensor, self.sensor(trainings[train]["trajectory"]), seed, c["fits"][kind] + ["--" + est], tag, folder + "/" + sname)
        m = matrix(fit)
        err = np.sqrt(np.nanmean([(m[i, j] - planted[i, j]) ** 2 for (i, j) in OFF])) * 1e6
        model = self.run.path("models", tag, "seed%d.json" % seed)
        row = {"training": train, "sensor": sname, "surfaces": kind, "estimation": est, "seed": seed, "offdiag_rms_err_urad": err,
               "chosen": fit["summary"]["details"].get("estimation_chosen", est),
               "train_rms_dph": float(np.mean(fit["residual_rms_dph"])), "bic": fit_bic(fit), "rate_order": surface_order(fit, "sf_rate_order"), "cross_order": surface_order(fit, "sf_cross_order"),
               "time_s": fit["summary"]["time_s"]}
        for flight in c["flights"]:
            row[flight + "_m"] = self.cof(model, sensor, flight)
        return row

    def simulate_and_fit_tagged(self, sensor, trajectory, seed, calibrate, model_tag, data_tag):
        """simulate_and_fit with the recording shared between fits of the same sensor."""
        rec = self.run.path("data", data_tag, "seed%d.csv" % seed)
        args = ["simulate", "--sensor", self.sensor(sensor), "--trajectory", trajectory, "--seed", seed, "--out", rec]
        if seed == 0:
            args.insert(1, "--noise-free")
        self.run.run(args, rec)
        model = self.run.path("models", model_tag, "seed%d.json" % seed)
        self.run.run(["calibrate", "--model", "triad", "--recording", rec] + calibrate + ["--out", model], model)
        return load_json(model)


    # --- independent generator ------------------------------------------------------------------------
    def independent(self):
        c = self.cfg["independent"]
        seeds = {case: list(range(c["first_seed"], c["first_seed"] + spec.get("runs", c["runs"]))) for case, spec in c["cases"].items()}
        gen = os.path.join(HERE, "independent_generator.py")

        def one(job):
            case, seed = job
            cubic = c["cases"][case]["cubic_ppm_per_dps2"]
            rec, truth = self.run.path("data", "independent", case, "seed%d.csv" % seed), self.run.path("data", "independent", case, "seed%d.json" % seed)
            if self.run.force or not os.path.exists(truth):
                import subprocess
                subprocess.run([sys.executable, gen, "--seed", str(seed), "--out", rec, "--truth", truth,
                                "--cubic-ppm-per-dps2", str(cubic)], check=True)
            t = load_json(truth)
            fits = {}
            for name, args in c["cases"][case]["fits"].items():
                model = self.run.path("models", "independent", case, name, "seed%d.json" % seed)
                self.run.run(["calibrate", "--model", "triad", "--recording", rec] + args + ["--out", model], model)
                fits[name] = load_json(model)
            return case, seed, t, fits

        results = self.parallel(one, [(case, s) for case in c["cases"] for s in seeds[case]])
        rows = []
        for case in c["cases"]:
            res = [r for r in results if r[0] == case]
            truth = np.array([r[2]["M"] for r in res])
            crb = np.array([r[2]["crb"] for r in res])
            estimators = {name: (np.array([matrix(r[3][name]) for r in res]), np.array([matrix(r[3][name], "sigma") for r in res]))
                          for name in c["cases"][case]["fits"]}
            estimators["numpy lstsq (peer)"] = (np.array([r[2]["numpy_lstsq"] for r in res]), None)
            estimators["rate-table +-turns (peer)"] = (np.array([r[2]["rate_table"] for r in res]), None)
            for name, (est, sig) in estimators.items():
                err = np.array([[est[k, i, j] - truth[k, i, j] for (i, j) in OFF] for k in range(len(res))])
                diag = np.array([[est[k, i, i] - truth[k, i, i] for i in range(3)] for k in range(len(res))])
                row = {"case": case, "estimator": name, "runs": len(res), "offdiag_rms_err_urad": float(np.sqrt(np.mean(err ** 2))) * 1e6,
                       "offdiag_mean_err_urad": float(np.mean(np.abs(err.mean(axis=0)))) * 1e6,
                       "diag_rms_err_ppm": float(np.sqrt(np.mean(diag ** 2))) * 1e6,
                       "crb_urad": float(np.mean([crb[k, i, j] for k in range(len(res)) for (i, j) in OFF])) * 1e6}
                if sig is not None:
                    z = np.array([[(est[k, i, j] - truth[k, i, j]) / sig[k, i, j] for (i, j) in OFF] for k in range(len(res))])
                    row.update({"sigma_reported_urad": float(np.nanmean([sig[k, i, j] for k in range(len(res)) for (i, j) in OFF])) * 1e6,
                                "cover_1sigma": float(np.mean(np.abs(z) <= 1)), "inside_3sigma": float(np.mean(np.abs(z) <= 3))})
                rows.append(row)
        cols = ["case", "estimator", "runs", "offdiag_rms_err_urad", "offdiag_mean_err_urad", "diag_rms_err_ppm", "crb_urad",
                "sigma_reported_urad", "cover_1sigma", "inside_3sigma"]
        write_csv(os.path.join(self.out, "independent.csv"), rows, cols)
        text = ("# Triads from an independent generator\n\n`independent_generator.py`: its own planted matrices K = diag(1+s)(I+L)R, "
                "a 100 Hz MEMS-like sensor (0.004 deg/s/sqrt(Hz)), its own motion programme with single-axis and diagonal (multi-axis) "
                "turns at 52 deg N, instantaneous samples. Cramer-Rao bound from the generator's own design matrix and true noise; "
                "peers on the same data: numpy least squares on the linear model, the rate-table estimator from opposite turns.\n\n")
        text += markdown_table(rows, cols)
        write_text(os.path.join(self.out, "independent.md"), text)
        print(text)

    # --- real sessions ----------------------------------------------------------------------------------
    def real(self):
        import import_imucal as imu
        root = self.cfg["real"]["imucal"]
        if not os.path.isdir(root):
            print("real: %s not found - skipped" % root)
            return
        text = "# Real sessions: imucal's Ferraris data, IMU-TK's Xsens data\n\n"
        snap = load_json(os.path.join(root, "tests", "snapshots", "example_cal.json"))
        parts = imu.annotated_session(os.path.join(root, "example_data", "annotated_session.csv"))
        peer = imu.ferraris_peer(parts, 204.8)
        text += "Our re-derivation of imucal's Ferraris calibration reproduces its snapshot `example_cal.json`: max |difference| %s.\n\n" % \
            ", ".join("%s %s" % (k, fmt(float(np.max(np.abs(np.array(peer[k]) - np.array(snap[k])))))) for k in ("K_g", "R_g", "b_g", "K_ga"))
        rec = self.run.path("data", "real", "annotated_session.csv")
        signs = imu.write_recording(rec, parts, 204.8, imu.NOMINAL_COUNTS_PER_DPS, imu.NOMINAL_COUNTS_PER_MPS2, "annotated_session.csv")
        text += "Turn directions read from the gyros: %s (imucal's default expects -360 deg, hence its R_g near -I).\n\n" % signs
        for name, args in (("ferraris", ["--set", "g_sensitivity=true"]), ("ferraris_no_g", [])):
            model = self.run.path("models", "real", "annotated_%s.json" % name)
            self.run.run(["calibrate", "--model", "triad", "--recording", rec] + args + ["--out", model], model)
            fit = load_json(model)
            ours = imu.triad_as_ferraris(fit, imu.NOMINAL_COUNTS_PER_DPS)
            k_imu, r_imu, b_imu = np.diag(np.array(snap["K_g"])), -np.array(snap["R_g"]), np.array(snap["b_g"])
            rows = []
            for i in range(3):
                rows.append({"entry": "K_%s (counts per deg/s)" % AXES[i], "gyrosid": ours["K"][i], "sigma": ours["K_sigma"][i], "imucal": k_imu[i],
                             "difference": ours["K"][i] - k_imu[i], "relative": (ours["K"][i] - k_imu[i]) / k_imu[i]})
            for i in range(3):
                for j in range(3):
                    if i != j:
                        rows.append({"entry": "R_%s%s (mrad)" % (AXES[i], AXES[j]), "gyrosid": ours["R"][i, j] * 1e3, "sigma": ours["R_sigma"][i, j] * 1e3,
                                     "imucal": r_imu[i, j] * 1e3, "difference": (ours["R"][i, j] - r_imu[i, j]) * 1e3, "relative": ""})
            for i in range(3):
                rows.append({"entry": "b_%s (counts)" % AXES[i], "gyrosid": ours["b"][i], "sigma": ours["b_sigma"][i], "imucal": b_imu[i],
                             "difference": ours["b"][i] - b_imu[i], "relative": ""})
            cols = ["entry", "gyrosid", "sigma", "imucal", "difference", "relative"]
            write_csv(os.path.join(self.out, "real_annotated_%s.csv" % name), rows, cols)
            text += "## annotated_session.csv, `calibrate --model triad %s` (%s)\n\nimucal's R_g compared as -R_g (its -360 deg convention).\n\n" % (
                " ".join(args), fit["reference"])
            text += markdown_table(rows, cols) + "\n"
            text += "Noise density %s rad/s/sqrt(Hz); notes: %s\n\n" % (fit["noise_density_radps_rt_hz"], fit["observable"]["notes"][:3])
        # The example session: gyrosid against the re-derived imucal (no snapshot of imucal exists for it).
        parts = imu.ferraris_session(os.path.join(root, "example_data", "example_ferraris_session.csv"),
                                     os.path.join(root, "example_data", "example_ferraris_session_list.json"))
        rec = self.run.path("data", "real", "example_ferraris_session.csv")
        signs = imu.write_recording(rec, parts, 102.4, 1.0, 1.0, "example_ferraris_session.csv")
        model = self.run.path("models", "real", "example_ferraris.json")
        self.run.run(["calibrate", "--model", "triad", "--recording", rec, "--set", "g_sensitivity=true", "--out", model], model)
        fit = load_json(model)
        ours = imu.triad_as_ferraris(fit, 1.0)
        peer = imu.ferraris_peer(parts, 102.4, expected_angle=360.0 * signs["x_rot"])
        rows = []
        for i in range(3):
            rows.append({"entry": "K_%s" % AXES[i], "gyrosid": ours["K"][i], "sigma": ours["K_sigma"][i], "imucal_method": peer["K_g"][i, i],
                         "difference": ours["K"][i] - peer["K_g"][i, i]})
        for i in range(3):
            for j in range(3):
                if i != j:
                    rows.append({"entry": "R_%s%s (mrad)" % (AXES[i], AXES[j]), "gyrosid": ours["R"][i, j] * 1e3, "sigma": ours["R_sigma"][i, j] * 1e3,
                                 "imucal_method": peer["R_g"][i, j] * 1e3, "difference": (ours["R"][i, j] - peer["R_g"][i, j]) * 1e3})
        cols = ["entry", "gyrosid", "sigma", "imucal_method", "difference"]
        write_csv(os.path.join(self.out, "real_example_ferraris.csv"), rows, cols)
        text += "## example_ferraris_session.csv (deg/s, 102.4 Hz), turn signs %s\n\nAgainst imucal's method (our re-derivation, with the observed turn direction).\n\n" % signs
        text += markdown_table(rows, cols) + "\n"
        text += self.xsens_note()
        write_text(os.path.join(self.out, "real.md"), text)
        print(text)

    def xsens_note(self):
        """IMU-TK's Xsens session: gyrosid on its static holds (bias, noise; M not determined) against our
        re-derivation of IMU-TK's gravity-referenced calibration (import_imutk.py)."""
        import import_imutk as tk
        root = self.cfg["real"]["imu_tk"]
        if not os.path.isdir(root):
            return "## IMU-TK's Xsens session\n\n%s not found - skipped\n" % root
        t, gyro, acc, holds = tk.load_session(root)
        peer = tk.imutk_peer(t, gyro, acc, holds)
        planted, exact, _ = tk.synthetic_check(seed=1, noise_counts=0.0)
        z, z_ours, err_ours = [], [], []
        for k in range(1, 21):  # synthetic sessions with planted T K: the peer and gyrosid's reference=gravity
            ts, gs, accs, planted_k = tk.synthetic_session(seed=k)
            holds_k = tk.static_intervals(ts, accs)
            peer_k = tk.imutk_peer(ts, gs, accs, holds_k)
            z.append(((peer_k["I_plus_M"] - planted_k) / peer_k["sigma"]).ravel())
            rec_k = self.run.path("data", "real", "synthetic_turns_seed%d.csv" % k)
            tk.write_recording(rec_k, ts, gs, tk.accel_calibration(accs, holds_k)[1](accs), holds_k, "synthetic seed %d" % k, turns=True)
            model_k = self.run.path("models", "real", "synthetic_turns_seed%d.json" % k)
            self.run.run(["calibrate", "--model", "triad", "--recording", rec_k, "--out", model_k], model_k)
            fk = load_json(model_k)
            z_ours.append(((matrix(fk) + np.eye(3) - planted_k) / matrix(fk, "sigma")).ravel())
            err_ours.append(np.abs(matrix(fk) + np.eye(3) - planted_k).max())
        z, z_ours = np.array(z), np.array(z_ours)
        _, acc_cal = tk.accel_calibration(acc, holds)
        rec = self.run.path("data", "real", "xsens_holds.csv")
        tk.write_recording(rec, t, gyro, acc_cal(acc), holds, "imu_tk/bin/test_data/xsens_{acc,gyro}.mat")
        model = self.run.path("models", "real", "xsens_holds.json")
        self.run.run(["calibrate", "--model", "triad", "--recording", rec, "--out", model], model)
        fit = load_json(model)
        model_g = self.run.path("models", "real", "xsens_holds_g.json")
        self.run.run(["calibrate", "--model", "triad", "--recording", rec, "--set", "g_sensitivity=true", "--out", model_g], model_g)
        fit_g = load_json(model_g)
        # gyrosid's own M: the hand turns too, known by the holds' gravity directions (reference=gravity).
        rec_t = self.run.path("data", "real", "xsens_turns.csv")
        tk.write_recording(rec_t, t, gyro, acc_cal(acc), holds, "imu_tk/bin/test_data/xsens_{acc,gyro}.mat", turns=True)
        model_t = self.run.path("models", "real", "xsens_gravity.json")
        self.run.run(["calibrate", "--model", "triad", "--recording", rec_t, "--out", model_t], model_t)
        fit_t = load_json(model_t)
        grav, grav_sigma = matrix(fit_t), matrix(fit_t, "sigma")
        hold_bias = np.array([np.degrees((gyro[b:e].mean(axis=0) - tk.ZERO_COUNTS) / tk.GYRO_COUNTS_PER_RADPS) * 3600.0 for b, e in holds])
        hold_se = np.array([np.degrees(gyro[b:e].std(axis=0) / math.sqrt(e - b) / tk.GYRO_COUNTS_PER_RADPS) * 3600.0 for b, e in holds])
        ours, ours_sigma = matrix(fit), matrix(fit, "sigma")
        rows = []
        for i in range(3):
            for j in range(3):
                unit = "" if i == j else " (mrad)"
                scale = 1.0 if i == j else 1e3
                peer_value = peer["I_plus_M"][i, j] - (1.0 if i == j else 0.0)
                rows.append({"entry": "M_%s%s%s" % (AXES[i], AXES[j], unit), "imutk_method": peer_value * scale,
                             "sigma": peer["sigma"][i, j] * scale,
                             "gyrosid_gravity": grav[i, j] * scale, "gravity_sigma": grav_sigma[i, j] * scale,
                             "difference": (grav[i, j] - peer_value) * scale,
                             "difference_in_sigma": (grav[i, j] - peer_value) / math.hypot(grav_sigma[i, j], peer["sigma"][i, j]),
                             "gyrosid": "not determined" if np.isnan(ours[i, j]) else ours[i, j] * scale,
                             "gyrosid_sigma": "" if np.isnan(ours_sigma[i, j]) else ours_sigma[i, j] * scale})
        peer_bias = np.degrees((peer["bias_counts"] - tk.ZERO_COUNTS) / tk.GYRO_COUNTS_PER_RADPS) * 3600.0
        for i in range(3):
            rows.append({"entry": "b_%s (deg/h at 6258 counts per rad/s)" % AXES[i], "imutk_method": peer_bias[i], "sigma": "",
                         "gyrosid_gravity": fit_t["bias_dph"]["value"][i], "gravity_sigma": fit_t["bias_dph"]["sigma"][i],
                         "gyrosid": fit["bias_dph"]["value"][i], "gyrosid_sigma": fit["bias_dph"]["sigma"][i]})
        for i in range(3):
            rows.append({"entry": "b_%s with G fitted" % AXES[i], "imutk_method": "", "sigma": "",
                         "gyrosid": fit_g["bias_dph"]["value"][i], "gyrosid_sigma": fit_g["bias_dph"]["sigma"][i]})
        for i in range(3):
            for j in range(3):
                rows.append({"entry": "G_%s%s (deg/h per m/s^2)" % (AXES[i], AXES[j]), "imutk_method": "", "sigma": "",
                             "gyrosid": fit_g["g_sensitivity_dph_per_mps2"][i][j], "gyrosid_sigma": fit_g["g_sensitivity_sigma_dph_per_mps2"][i][j]})
        cols = ["entry", "imutk_method", "sigma", "gyrosid_gravity", "gravity_sigma", "difference", "difference_in_sigma", "gyrosid", "gyrosid_sigma"]
        write_csv(os.path.join(self.out, "real_xsens.csv"), rows, cols)
        text = ("## IMU-TK's Xsens session (xsens_acc.mat, xsens_gyro.mat: raw counts, 100 Hz, 511.7 s)\n\n"
                "gyrosid's own M (columns gyrosid_gravity): `calibrate --model triad` on the holds *and* the hand turns "
                "(`xsens_turns.csv`: position_id 0 in motion, `# reference: gravity`; %s) - each turn's compensated gyro "
                "output integrated on SO(3) must carry the gravity direction of the hold before it into that of the hold "
                "after it (solvers/triad/gravity_turns.h), the holds fix the biases; accelerometer directions from the "
                "importer's |a| = g calibration. Against the IMU-TK-method peer: largest difference %.3g mrad off the "
                "diagonal, %.3g ppm on it, %.2f combined sigmas at most. The columns gyrosid / gyrosid_sigma are the "
                "holds-only fit (no turns: M not determined). On the 20 synthetic sessions below (planted T K) gyrosid's "
                "largest error per session is %.2g..%.2g and its errors spread %.2f times its sigmas (the peer's: %.2f): "
                "the same too-narrow intervals, for the same reason (each hold's gravity direction, shared by two turns, "
                "is taken as exact).\n\n"
                % (fit_t["reference"], max(abs(grav[i, j] - peer["I_plus_M"][i, j]) for i in range(3) for j in range(3) if i != j) * 1e3,
                   max(abs(grav[i, i] - peer["I_plus_M"][i, i] + 1.0) for i in range(3)) * 1e6,
                   max(abs(r["difference_in_sigma"]) for r in rows if "difference_in_sigma" in r),
                   min(err_ours), max(err_ours), float(z_ours.std()), float(z.std())) +
                "### The holds-only fit and the peer\n\n"
                "%d static holds found by IMU-TK's accelerometer-variance detector, %d hand turns between them. Given the "
                "holds only (`xsens_holds.csv`, reference 0, Earth rate neglected), gyrosid determines the "
                "biases and noise (%s rad/s/sqrt(Hz)) but no entry of M: it reports all nine as not determined (%d "
                "determined combinations) rather than a number. The peer (imutk_method columns) is our re-derivation of IMU-TK's method "
                "(accelerometer by |a| = g over the holds, then the gyro's T K by carrying each hold's gravity "
                "direction through the integrated turn to the next; residual rms %.2g in unit-vector terms; sigmas "
                "from its Gauss-Newton covariance; on synthetic sessions with planted parameters, `synthetic_check()`, it "
                "recovers I + M to %.1g noise-free; with noise its errors spread %.2g times its sigmas (20 seeds, all nine "
                "entries): those sigmas are too small, presumably because the noise of each hold's gravity direction, shared by the turns "
                "before and after it, is not in them - read the peer's intervals as that much wider). M_ii = the true scale over IMU-TK's initial 1/6258 rad/s per "
                "count, minus 1. Biases: gyrosid's is the holds' common constant, IMU-TK's the mean of the 50 s "
                "static start (one orientation). The holds' own means scatter by %s deg/h (standard deviation per gyro) "
                "against a standard error of %s deg/h each: the bias depends on the orientation (or drifts in step with it: one "
                "512 s session cannot tell the two apart). gyrosid's fit with "
                "`--set g_sensitivity=true` takes that up as G (rows G_ below) and its residual rms per gyro drops from "
                "%s to %s deg/h.\n\n"
                % (len(holds), peer["turns"], ", ".join("%.3g" % v for v in fit["noise_density_radps_rt_hz"]),
                   fit["observable"]["independent_combinations"], peer["residual_rms"], np.max(np.abs(exact - planted)), float(z.std()),
                   ", ".join("%.0f" % v for v in hold_bias.std(axis=0)), ", ".join("%.0f" % v for v in hold_se.mean(axis=0)),
                   ", ".join("%.0f" % v for v in fit["residual_rms_dph"]), ", ".join("%.0f" % v for v in fit_g["residual_rms_dph"])))
        return text + markdown_table(rows, cols) + "\n"

    # --- the targets of issue 10, quoted from the parts' tables --------------------------------------------
    def summary(self):
        import csv
        read = lambda name: list(csv.DictReader(open(os.path.join(self.out, name)))) if os.path.exists(os.path.join(self.out, name)) else []
        num = lambda v: float(v) if v not in ("", None) else float("nan")
        verdict = lambda ok: "met" if ok else "missed"
        lines = ["# Issue 10 targets, from the tables in this folder (`run.py summary` rewrites this file)\n"]
        mc = [r for r in read("monte_carlo.csv") if r["unit"] == "urad"]
        if mc:
            sig = max(num(r["sigma_reported"]) for r in mc)
            floor = num(mc[0]["floor"])
            cover = [num(r["cover_1sigma"]) for r in mc]
            inside = [num(r["inside_3sigma"]) for r in mc]
            lines.append("* Off-diagonal sigma <= 25 urad near the floor (monte_carlo.md): reported <= %s urad, MC %s..%s urad, "
                         "floor %s urad - %s." % (fmt(sig), fmt(min(num(r["sigma_mc"]) for r in mc)), fmt(max(num(r["sigma_mc"]) for r in mc)),
                                                 fmt(floor), verdict(sig <= 25 and sig <= 1.1 * floor)))
            lines.append("* Planted inside 3 sigma in >= 99 %% of runs: per entry %s..%s - %s." % (fmt(min(inside), 4), fmt(max(inside), 4), verdict(min(inside) >= 0.99)))
            lines.append("* 1-sigma coverage in [0.6, 0.76]: %s..%s - %s." % (fmt(min(cover)), fmt(max(cover)), verdict(0.6 <= min(cover) and max(cover) <= 0.76)))
        cmp = read("compare.csv")
        if cmp:
            flights = [k[:-2] for k in cmp[0] if k.endswith("_m")]
            for r in cmp:
                r.setdefault("training", "rate_sweep")
            # Two criteria, both reported. Interval ("not worse beyond the paired 95 % interval"): joint worse / better
            # on a flight when the 95 % bootstrap interval of the median paired ratio joint/sequential lies above /
            # below 1, else a tie. Literal: the median ratio itself <= 1 (at least as good), < 1 (strictly better).
            verdicts, medians = {}, {}
            for g in paired_summary(cmp, flights, self.cfg["compare"]["seeds"]):
                word = interval_word(g)
                if g["quantity"] == "offdiag_rms_err_urad":
                    lines.append("* Joint vs sequential, %s training, %s sensor, %s surfaces (compare.md; median joint/sequential over %s seeds "
                                 "[95 %% interval], joint wins, sign-test p):" % (g["training"], g["sensor"], g["surfaces"], g["joint_wins"].split("/")[1]))
                    lines.append("  off-diagonal error %s [%s], %s, p %s - %s;" % (fmt(g["median_ratio"], 5), g["ratio_ci95"], g["joint_wins"], fmt(g["sign_p"], 2), word))
                elif g["quantity"].endswith("_m"):
                    lines.append("  %s flight %s [%s], %s, p %s - %s;" % (g["quantity"][:-2], fmt(g["median_ratio"], 5), g["ratio_ci95"], g["joint_wins"], fmt(g["sign_p"], 2), word))
                    key = (g["training"], g["sensor"], g["surfaces"])
                    verdicts.setdefault(key, []).append(word)
                    medians.setdefault(key, []).append(g["median_ratio"])
            orders = {}  # "rate/cross" where the row has both, else the cross order
            for r in cmp:
                if r.get("cross_order") not in (None, "") and int(r["seed"]) > 0:
                    order = "%s/%s" % (r["rate_order"], r["cross_order"]) if r.get("rate_order") not in (None, "") else r["cross_order"]
                    orders.setdefault((r["training"], r["sensor"], r["surfaces"], r["estimation"]), []).append(order)
            # The CLI's defaults: classical surfaces with the orders order_criterion=bic_lr chooses (kind `classical`), and rbf.
            default = {k: v for k, v in verdicts.items() if k[2] in ("classical", "rbf")}
            if any(k[2] == "classical" for k in orders):
                lines.append("* Orders (rate / cross) the default classical surfaces chose (auto, order_criterion=bic_lr), noisy seeds: %s." % "; ".join(
                    "%s/%s/%s %s" % (k[0], k[1], k[3], ", ".join("order %s in %d" % (o, v.count(o)) for o in sorted(set(v))))
                    for k, v in sorted(orders.items()) if k[2] == "classical"))
            for label, groups in (("the CLI's default surfaces (classical = orders auto by bic_lr, rbf)", default),
                                  ("every surface family fitted (also classical_bic, classical_aic, classical_separable, classical_cross2)", verdicts)):
                lines += comparative_target_lines("Joint", label, groups, medians, flights)
        auto = read("compare_auto.csv")
        if cmp and auto:
            verdicts, medians = {}, {}
            for g in paired_summary(auto + cmp, flights, self.cfg["compare"]["seeds"], "auto", "sequential"):
                if g["quantity"].endswith("_m"):
                    key = (g["training"], g["sensor"], g["surfaces"])
                    verdicts.setdefault(key, []).append(interval_word(g))
                    medians.setdefault(key, []).append(g["median_ratio"])
            chosen = chosen_by_cell(auto)
            lines.append("* estimation=auto (`--auto`, compare_auto.md): the joint fit returned in %s; the sequential in every other fit." % "; ".join(
                "%s/%s/%s %d of %d" % (k + (v.count("joint"), len(v))) for k, v in sorted(chosen.items()) if "joint" in v))
            lines += comparative_target_lines("Auto", "the CLI's default surfaces", verdicts, medians, flights)
            coupled = sorted(k for k, v in chosen.items() if k[1] == "rate_nonlinear" and "joint" in v)
            lines.append("  where the test found the surfaces coupled with M (auto returned the joint fit): %s." % "; ".join(
                "%s/%s %s" % (k[0], k[2], ", ".join("%s %s %s" % (f, fmt(m, 4), w) for f, m, w in zip(flights, medians[k], verdicts[k]))) for k in coupled))
        more = read("compare_more.csv")
        if more:
            seeds = sorted({int(r["seed"]) for r in more if int(r["seed"]) > 0})
            flights = [k[:-2] for k in more[0] if k.endswith("_m")]
            for g in paired_summary(more, flights, seeds):
                if g["quantity"].endswith("_m") and g["ci_lo"] > 1:
                    lines.append("* More seeds (compare_more.md, seeds 1..%d): %s/%s/%s %s flight %s [%s], %s, sign-test p %s - still above 1 "
                                 "beyond the paired interval." % (len(seeds), g["training"], g["sensor"], g["surfaces"], g["quantity"][:-2],
                                                                  fmt(g["median_ratio"], 5), g["ratio_ci95"], g["joint_wins"], fmt(g["sign_p"], 2)))
        ind = read("independent.csv")
        if ind:
            err = {r["estimator"]: num(r["offdiag_rms_err_urad"]) for r in ind if r["case"] == "rate_nonlinear"}
            lin = [r for r in ind if r["case"] == "linear" and r["estimator"] == "gyrosid"][0]
            lines.append("* Independent generator, linear sensor (independent.md): off-diagonal rms error %s urad against a "
                         "Cramer-Rao bound of %s urad, 1-sigma coverage %s, inside 3 sigma %s." % (fmt(num(lin["offdiag_rms_err_urad"])),
                         fmt(num(lin["crb_urad"])), fmt(num(lin["cover_1sigma"])), fmt(num(lin["inside_3sigma"]))))
            if "gyrosid_joint" in err:
                lines.append("* Joint strictly better when the surfaces are rate-nonlinear, by parameter error (independent.md): joint %s urad, "
                             "sequential %s urad, no surface %s urad - %s." % (fmt(err["gyrosid_joint"]), fmt(err["gyrosid_sequential"]),
                             fmt(err["gyrosid_none"]), verdict(err["gyrosid_joint"] < err["gyrosid_sequential"])))
        for name, label in (("real_annotated_ferraris.csv", "with G"), ("real_annotated_ferraris_no_g.csv", "without G")):
            rows = read(name)
            if rows:
                k = max(abs(num(r["relative"])) for r in rows if r["entry"].startswith("K_"))
                m = max(abs(num(r["difference"])) for r in rows if r["entry"].startswith("R_"))
                lines.append("* imucal's annotated session, %s (real.md): scale factors within %s %% of imucal's (target 0.5 %%), "
                             "misalignment within %s mrad per entry (target 2 mrad) - %s." % (label, fmt(100 * k), fmt(m), verdict(k <= 0.005 and m <= 2)))
        xs = read("real_xsens.csv")
        if xs:
            m = [r for r in xs if r["entry"].startswith("M_")]
            off = max(abs(num(r["difference"])) for r in m if "mrad" in r["entry"])
            dia = max(abs(num(r["difference"])) for r in m if "mrad" not in r["entry"])
            zmax = max(abs(num(r["difference_in_sigma"])) for r in m)
            lines.append("* IMU-TK's Xsens session (real.md): gyrosid's own M from the hand turns (reference=gravity) against the "
                         "IMU-TK-method peer: off-diagonal within %s mrad, scale factors within %s ppm, at most %s combined sigmas "
                         "(no IMU-TK output exists to compare with; the peer re-derives its method)." % (fmt(off), fmt(dia * 1e6), fmt(zmax)))
        text = "\n".join(lines) + "\n"
        write_text(os.path.join(self.out, "summary.md"), text)
        print(text)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("part", nargs="?", default="all", choices=["mc", "compare", "more", "auto", "independent", "real", "summary", "all"])
    add_gyrosid_argument(p)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--force", action="store_true")
    p.add_argument("--seeds", type=int, default=0, help="compare: only the first N noisy seeds of config.yaml (0: all); more: seeds 1..N (0: 60)")
    p.add_argument("--kinds", default="", help="compare: refit only these surface kinds (comma-separated), keep the others' rows; auto: the kinds to fit (default classical,rbf)")
    p.add_argument("--cells", default="", help="more: compare cells training/sensor/kind, comma-separated")
    p.add_argument("--estimation", default="", choices=["", "joint", "sequential", "auto"],
                   help="mc: fit the same recordings in this mode, results/monte_carlo_<mode>.md (default: the CLI's default, monte_carlo.md)")
    args = p.parse_args()
    e = Experiment(args)
    parts = {"mc": e.monte_carlo, "compare": e.compare, "more": e.more, "auto": e.auto, "independent": e.independent, "real": e.real, "summary": e.summary}
    for name, fn in parts.items():
        if args.part == name or (args.part == "all" and name not in ("more", "auto")):
            fn()


if __name__ == "__main__":
    main()
