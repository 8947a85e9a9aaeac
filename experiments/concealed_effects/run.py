#!/usr/bin/python3
"""Concealed effects: does `gyrosid explain` find, name and model an effect hidden in a recording, stay
silent when nothing is missing, and say "unexplained" when the effect is outside its library - on
recordings of gyrosid's own simulator and on recordings of an independent generator (independent.py)?

    experiments/concealed_effects/run.py [--gyrosid build/gyrosid] [--out experiments/concealed_effects/results]
                                         [--generators simulator,independent] [--seeds N] [--jobs 2]
                                         [--budget-min M] [--force]

Writes results/summary.md (both generators side by side against the targets, then each one's tables: power
curves, naming, parameters and intervals, held-out excess removed, false discoveries on the controls,
localisation, run time), results/runs.csv (one row per recording) and results/power.png. Recordings and
explain outputs stay under results/runs/ and results/independent/ (reused on a rerun); --budget-min stops
starting new recordings after M minutes, so a long sweep runs in resumable chunks.
"""
import argparse
import concurrent.futures
import json
import os
import sys
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import generate as gen  # noqa: E402
import independent_cases  # noqa: E402
from gyrosid_experiments import Runner, add_gyrosid_argument, fmt, gnuplot, markdown_table, write_csv, write_text  # noqa: E402

ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


class Experiment:
    def __init__(self, args):
        self.cfg = yaml.safe_load(open(os.path.join(HERE, "config.yaml")))
        self.run = Runner(args.gyrosid, args.out, args.force)
        self.force = args.force
        self.sensor = os.path.join(HERE, self.cfg["sensor"])
        self.base = yaml.safe_load(open(self.sensor))
        self.sigma = self.cfg["noise_sigma_dph"]
        self.shapes = {}
        self.model = None

    def simulation(self):
        """The simulation of the first generator: a grey-box model calibrated on a separate dual scan."""
        s = self.cfg["simulation"]
        cal = self.run.path("simulation", "calibration.csv")
        self.run.run(["simulate", "--sensor", self.sensor, "--trajectory", s["trajectory"], "--seed", s["seed"], "--out", cal], cal)
        self.model = self.run.path("simulation", "model.json")
        self.run.run(["calibrate", "--recording", cal] + s["calibrate"] + ["--out", self.model], self.model)

    def trajectory(self, name):
        return self.cfg["trajectories"][name]

    def sensor_shape(self, trajectory, **variant):
        """Noise-free (variant - base) in deg/h along a trajectory: an effect of the sensor model itself."""
        key = (trajectory, tuple(sorted(variant.items())))
        if key not in self.shapes:
            d = self.run.path("shapes", "%s_%s" % (trajectory, "_".join("%s%s" % kv for kv in sorted(variant.items()))), "x")[:-2]
            os.makedirs(d, exist_ok=True)
            base, var = os.path.join(d, "base.csv"), os.path.join(d, "variant.csv")
            gen.sensor_variant(self.base, os.path.join(d, "sensor.yaml"), **variant)
            for sensor, out in ((self.sensor, base), (os.path.join(d, "sensor.yaml"), var)):
                self.run.run(["simulate", "--sensor", sensor, "--trajectory", self.trajectory(trajectory), "--noise-free", "--seed", 1, "--out", out], out)
            _, b = gen.read_recording(base)
            _, v = gen.read_recording(var)
            self.shapes[key] = ((v["gyro_dps"] - b["gyro_dps"]) * 3600.0, b)
        return self.shapes[key]

    def build(self, job):
        """Writes the recording of a job (if absent) and its truth; returns the truth."""
        d = job["dir"]
        rec, truth_path = os.path.join(d, "recording.csv"), os.path.join(d, "truth.json")
        if os.path.exists(truth_path) and not self.force:
            return json.load(open(truth_path))
        os.makedirs(d, exist_ok=True)
        effect, m, traj = job.get("effect"), job.get("magnitude"), job["trajectory"]
        variant, truth = {}, {"effect": effect, "magnitude": m}
        if effect in ("shupe", "scale_factor_asymmetry"):
            key = "shupe" if effect == "shupe" else "asymmetry"
            shape, cols0 = self.sensor_shape(traj, **{key: 1.0})
            c = m * self.sigma / gen.rms(gen.unabsorbed(cols0, shape))
            variant[key] = c
            truth["value"] = c
        elif effect == "thermal_lag":
            variant["coil_tau"] = job["tau_s"]
            shape, cols0 = self.sensor_shape(traj, coil_tau=job["tau_s"])
            truth["value"] = job["tau_s"]
            truth["magnitude"] = gen.rms(gen.unabsorbed(cols0, shape)) / self.sigma
        if job.get("noise"):
            variant["noise"] = job["noise"]
        if job.get("perturb"):
            variant["perturb"] = True
        sensor = gen.sensor_variant(self.base, os.path.join(d, "sensor.yaml"), **variant)
        self.run.run(["simulate", "--sensor", sensor, "--trajectory", self.trajectory(traj), "--seed", job["seed"], "--out", rec], rec)
        meta, cols = gen.read_recording(rec)
        gen.add_channels(cols, job["seed"])
        if job.get("tilt_per_plateau"):
            gen.tilt_per_plateau(cols)
        python_effect = effect and effect not in ("shupe", "scale_factor_asymmetry", "thermal_lag")
        if python_effect:
            shape = gen.shape_of(effect, cols, job)
            c = m * self.sigma / gen.rms(gen.unabsorbed(cols, shape))
            cols["gyro_dps"] = cols["gyro_dps"] + c * shape / 3600.0
            truth["value"] = c
            if effect == "warmup_transient":
                truth["tau_s"] = job["tau_s"]
        outside = job.get("outside")
        if outside:
            t = cols["t_s"]
            shape = cols["supply_v"] - 5.0 if outside == "supply_voltage" else (t > t[0] + 0.6 * (t[-1] - t[0])).astype(float)
            if outside == "bias_step":
                truth["t_step_s"] = float(t[0] + 0.6 * (t[-1] - t[0]))
            c = m * self.sigma / gen.rms(gen.unabsorbed(cols, shape))
            cols["gyro_dps"] = cols["gyro_dps"] + c * shape / 3600.0
            truth["value"] = c
        # The planted signal the simulation cannot absorb, for the functional check of the refit.
        planted = np.zeros_like(cols["t_s"])
        if effect in ("shupe", "scale_factor_asymmetry"):
            planted = truth["value"] * self.sensor_shape(traj, **{("shupe" if effect == "shupe" else "asymmetry"): 1.0})[0]
        elif effect == "thermal_lag":
            planted = self.sensor_shape(traj, coil_tau=job["tau_s"])[0]
        elif python_effect:
            planted = truth["value"] * gen.shape_of(effect, cols, job)
        np.save(os.path.join(d, "planted.npy"), gen.unabsorbed(cols, planted))
        gen.write_recording(rec, meta, cols)
        json.dump(truth, open(truth_path, "w"))
        return truth

    def do(self, job):
        if job.get("generator") == "independent":
            truth = independent_cases.build(job)
            out = os.path.join(job["dir"], "explain")
            self.run.run(["explain", "--recording", os.path.join(job["dir"], "recording.csv"), "--out", out] +
                         independent_cases.explain_args(job), os.path.join(out, "explain.json"))
            return independent_cases.score(job, truth, json.load(open(os.path.join(out, "explain.json"))), job["dir"])
        truth = self.build(job)
        d = job["dir"]
        out = os.path.join(d, "explain")
        self.run.run(["explain", "--recording", os.path.join(d, "recording.csv"), "--model", self.model, "--seed", job["seed"],
                      "--out", out] + [str(a) for a in self.cfg["explain_args"]], os.path.join(out, "explain.json"))
        return score(job, truth, json.load(open(os.path.join(out, "explain.json"))), d, self.sigma)


PARAMETER = {}


def score(job, truth, ex, d, sigma):
    effects = ex["effects"]
    names = [e["id"] for e in effects]
    row = {"generator": "simulator", "group": job["group"], "case": job["case"], "seed": job["seed"], "magnitude": truth.get("magnitude"),
           "verdict": ex["verdict"], "named": " ".join(names), "run_time_s": ex["run_time_s"],
           "heldout_ratio": ex["fit"]["heldout_rms_after_dph"] / sigma,
           "heldout_outside_support": ex["recording"].get("heldout_outside_support", 0),
           "heldout_samples": ex["recording"]["samples"] - ex["recording"]["training_samples"],
           "unexplained": " ".join(sorted({u["kind"] + (":" + u["channel"] if u["channel"] else "") for u in ex["unexplained"]}))}
    target = truth.get("effect")
    if target:
        first = effects[0] if effects else None
        row["detected"] = any(target == e["id"] or target in e["alternatives"] for e in effects)
        row["correct"] = bool(first) and (first["id"] == target or target in first["alternatives"])
        row["ambiguous"] = bool(first) and first["id"] != target and target in first["alternatives"]
        row["wrong_extra"] = sum(1 for e in effects if e["id"] != target and target not in e["alternatives"])
        hit = next((e for e in effects if e["id"] == target), None)
        p = PARAMETER.get(target)
        if hit and p and p in hit["parameters"] and "value" in truth:
            est, ci = hit["parameters"][p], hit["confidence"].get(p)
            row["param_rel_err"] = abs(est - truth["value"]) / abs(truth["value"])
            row["param_covered"] = bool(ci) and ci[0] <= truth["value"] <= ci[1]
        # Functional check: the fitted correction (before - after) against the planted unabsorbable signal.
        planted = np.load(os.path.join(d, "planted.npy"))
        res = np.genfromtxt(os.path.join(d, "explain", "residuals.csv"), delimiter=",", names=True)
        fitted = res["residual_before_dph"] - res["residual_after_dph"]
        if hit:
            row["effect_rel_err"] = gen.rms(fitted - planted) / gen.rms(planted)
        # On the held-out samples explain confirms with (1), and on all of them (2: outside the training support).
        for key, held in (("heldout_excess_removed", res["heldout"] == 1), ("heldout_excess_removed_all", res["heldout"] > 0)):
            before, after = np.mean(res["residual_before_dph"][held] ** 2), np.mean(res["residual_after_dph"][held] ** 2)
            if before - sigma ** 2 > 0.05 * sigma ** 2:  # the white noise's variance is the floor
                row[key] = (before - after) / (before - sigma ** 2)
    if job.get("outside") == "bias_step":
        t_step = truth["t_step_s"]
        row["localised"] = ex["verdict"] == "unexplained_residual" and any(u["kind"] in ("time_window", "change_point", "trend_change") and
                               u["t_start_s"] - 600.0 <= t_step <= u["t_end_s"] + 600.0 for u in ex["unexplained"])
    return row


def jobs_of(cfg, out, seeds):
    jobs = []
    def add(group, case, seed, **kw):
        jobs.append(dict(kw, generator="simulator", group=group, case=case, seed=seed, dir=os.path.join(out, "runs", group, case, "seed%d" % seed)))
    for effect, spec in cfg["effects"].items():
        PARAMETER[effect] = spec.get("parameter")
        for i, m in enumerate(cfg["magnitudes"]):
            for seed in range(1, seeds + 1):
                kw = {"effect": effect, "magnitude": m, "trajectory": spec["trajectory"]}
                if effect == "thermal_lag":
                    kw["tau_s"] = spec["tau_s"][len(spec["tau_s"]) - 1 - i]
                elif "tau_s" in spec:
                    kw["tau_s"] = spec["tau_s"]
                add("effect", "%s@%s" % (effect, m), 100 * i + seed, **kw)
    for case, spec in cfg["confounded"].items():
        for seed in range(1, seeds + 1):
            kw = {"effect": spec["effect"], "magnitude": 0.5, "trajectory": spec["trajectory"]}
            for k in ("tau_s", "tilt_per_plateau"):
                if k in spec:
                    kw[k] = spec[k]
            if kw["effect"] == "warmup_transient" and "tau_s" not in kw:
                kw["tau_s"] = cfg["effects"]["warmup_transient"]["tau_s"]
            add("confounded", case, 1000 + seed, **kw)
    for case, spec in cfg["controls"].items():
        for seed in range(1, spec["seeds"] + 1):
            add("control", case, 2000 + seed, trajectory="cycles", noise=spec.get("noise"), perturb=spec.get("perturb", False))
    for case, spec in cfg["outside_library"].items():
        for seed in range(1, spec["seeds"] + 1):
            add("outside", case, 3000 + seed, trajectory="cycles", outside=case, magnitude=spec["magnitude"])
    return jobs


def rate(rows, key):
    vals = [r[key] for r in rows if key in r]
    return sum(1 for v in vals if v) / len(vals) if vals else float("nan")


def coverage(rows, planned):
    """One line per generator: recordings explained of those planned (a sweep cut short covers fewer)."""
    lines = []
    for g, n in planned.items():
        done = sum(1 for r in rows if r["generator"] == g)
        lines.append("- %s: %d of %d recordings explained%s\n" % (g, done, n, "" if done == n else
                     " (the sweep was cut short by its budget; every case's first seed ran before any second seed)"))
    return "".join(lines) + "\n"


def summarize(cfg, rows, out, planned):
    md = ["# Concealed effects\n\n", "Generated by `experiments/concealed_effects/run.py` on two generators: gyrosid's own simulator "
          "(with the grey-box simulation given to explain) and an independent generator (`independent.py`: another sensor, "
          "other programmes, other noise, effects written in other laws; explain given no simulation and no options).\n\n",
          coverage(rows, planned), both_generators_table(rows), independent_tables(rows)]
    rows = [r for r in rows if r["generator"] == "simulator"]
    if rows:
        md += simulator_tables(cfg, rows, out)
    write_text(os.path.join(out, "summary.md"), "".join(md))


def simulator_tables(cfg, rows, out):
    md = ["## Simulator (gyrosid simulate)\n\n",
          "Base sensor `sensor.yaml` (white noise %s deg/h per 1-Hz "
          "sample); simulation: a grey-box model calibrated on a separate dual scan (bias cubic in T, scale factor "
          "quadratic in rate and linear in T); recordings of 224 min (thermal cycles, 13,440 samples) or 476 min "
          "(classical soak, g-sensitivity). Magnitude = RMS of the part of the effect the simulation cannot absorb, in "
          "units of the per-sample noise.\n\n" % cfg["noise_sigma_dph"]]
    eff = [r for r in rows if r["group"] == "effect"]
    effects = list(cfg["effects"].keys())
    mags = cfg["magnitudes"]
    table, plot_blocks, plot_cmds = [], [], []
    for i, e in enumerate(effects):
        row = {"effect": e}
        pts = []
        for m in mags:
            rs = [r for r in eff if r["case"] == "%s@%s" % (e, m)]
            mag = np.mean([r["magnitude"] for r in rs]) if rs else m
            row["%s" % m] = "%s (%s)" % (fmt(rate(rs, "detected"), 2), fmt(rate(rs, "correct"), 2))
            pts.append((mag, rate(rs, "detected")))
        table.append(row)
        plot_blocks.append("$d%d << EOD\n%s\nEOD\n" % (i, "\n".join("%g %g" % p for p in sorted(pts))))
        plot_cmds.append("$d%d using 1:2 with linespoints lw 2 title '%s'" % (i, e))
    md += ["### Detection power (named, with correct first name in brackets) against magnitude\n\n",
           markdown_table(table, ["effect"] + ["%s" % m for m in mags], ["effect"] + ["%s sigma" % m for m in mags]),
           "\nFor the thermal lag the magnitude is set by its time constant (%s s, largest first); the column shows the "
           "configured step, the plot the measured magnitude.\n\n![power](power.png)\n\n" % cfg["effects"]["thermal_lag"]["tau_s"]]
    gnuplot(os.path.join(out, "power.png"), "".join(plot_blocks) +
            "set logscale x\nset grid\nset key outside right\nset xlabel 'magnitude (unabsorbable RMS / noise sigma)'\n"
            "set ylabel 'fraction named'\nset yrange [-0.05:1.05]\nset title 'Detection power of gyrosid explain'\nplot %s\n" % ", ".join(plot_cmds))

    strong = [r for r in eff if r["magnitude"] is not None and r["magnitude"] >= 0.25 - 1e-9]
    params = [r for r in strong if "param_rel_err" in r]
    funcs = [r for r in strong if "effect_rel_err" in r]
    held = [r["heldout_ratio"] for r in strong if r.get("detected")]
    summary = [
        {"metric": "naming correct (truth first, or in its ambiguity set), magnitude >= 0.25", "value": fmt(rate(strong, "correct"), 3), "target": ">= 0.9"},
        {"metric": "  of which honest ambiguity sets", "value": fmt(rate(strong, "ambiguous"), 3), "target": ""},
        {"metric": "recordings with a wrong extra effect, magnitude >= 0.25", "value": fmt(sum(1 for r in strong if r.get("wrong_extra")) / max(1, len(strong)), 3), "target": ""},
        {"metric": "parameter |relative error| median / 90th percentile", "value": "%s / %s" % (fmt(np.median([r["param_rel_err"] for r in params]), 3), fmt(np.percentile([r["param_rel_err"] for r in params], 90), 3)) if params else "-", "target": "<= 0.3"},
        {"metric": "parameter within 30 %", "value": fmt(np.mean([r["param_rel_err"] <= 0.3 for r in params]), 3) if params else "-", "target": ""},
        {"metric": "95 % interval coverage of the parameter", "value": fmt(rate(params, "param_covered"), 3), "target": "~0.95"},
        {"metric": "fitted effect |relative error| median (functional check)", "value": fmt(np.median([r["effect_rel_err"] for r in funcs]), 3) if funcs else "-", "target": ""},
        {"metric": "held-out rms after / noise sigma, median / max", "value": "%s / %s" % (fmt(np.median(held), 4), fmt(max(held), 4)) if held else "-", "target": "<= 1.10"},
        {"metric": "run time per recording (s), median / max", "value": "%s / %s" % (fmt(np.median([r["run_time_s"] for r in rows]), 3), fmt(max(r["run_time_s"] for r in rows), 3)), "target": "< 60"},
    ]
    md += ["### Summary (targets of issue 5)\n\n", markdown_table(summary, ["metric", "value", "target"])]

    ctrl = [r for r in rows if r["group"] == "control"]
    cases = sorted({r["case"] for r in ctrl})
    crow = [{"control": c, "recordings": len([r for r in ctrl if r["case"] == c]),
             "false discoveries": sum(1 for r in ctrl if r["case"] == c and r["verdict"] != "no_missing_physics"),
             "verdicts": ", ".join(sorted({r["verdict"] + (" (" + r["named"] + ")" if r["named"] else "") for r in ctrl if r["case"] == c}))}
            for c in cases]
    fd = sum(1 for r in ctrl if r["verdict"] != "no_missing_physics")
    md += ["\n### Negative controls (nothing missing from the physics)\n\n", markdown_table(crow, ["control", "recordings", "false discoveries", "verdicts"]),
           "\nFalse-discovery rate over all controls: %d / %d = %s (target <= 0.05).\n" % (fd, len(ctrl), fmt(fd / max(1, len(ctrl)), 3))]
    outside = [r for r in rows if r["group"] == "outside"]
    orow = [{"case": c, "recordings": len([r for r in outside if r["case"] == c]),
             "unexplained_residual": sum(1 for r in outside if r["case"] == c and r["verdict"] == "unexplained_residual"),
             "named an effect": sum(1 for r in outside if r["case"] == c and r["named"]),
             "localised as": ", ".join(sorted({r["unexplained"] for r in outside if r["case"] == c}))} for c in sorted({r["case"] for r in outside})]
    md += ["\n### Effects outside the library\n\n", markdown_table(orow, ["case", "recordings", "unexplained_residual", "named an effect", "localised as"])]
    conf = [r for r in rows if r["group"] == "confounded"]
    frow = [{"design": c, "note": cfg["confounded"][c]["note"], "correct or honest ambiguity": fmt(rate([r for r in conf if r["case"] == c], "correct"), 2),
             "named": "; ".join(sorted({r["named"] for r in conf if r["case"] == c}))} for c in cfg["confounded"]]
    md += ["\n### Confounded designs (magnitude 0.5)\n\n", markdown_table(frow, ["design", "note", "correct or honest ambiguity", "named"])]
    return md


def targets(rows):
    """The targets of issue 12 measured on one generator's rows."""
    strong = [r for r in rows if r["group"] in ("effect", "combination", "confounded") and r.get("magnitude") is not None
              and not np.isnan(r["magnitude"]) and r["magnitude"] >= 0.25 - 1e-9]
    ctrl = [r for r in rows if r["group"] == "control"]
    excess = [r["heldout_excess_removed"] for r in strong if r.get("correct") and "heldout_excess_removed" in r]
    excess_all = [r["heldout_excess_removed_all"] for r in strong if r.get("correct") and "heldout_excess_removed_all" in r]
    outside = [r["heldout_outside_support"] / max(1, r.get("heldout_samples", 1)) for r in rows if "heldout_outside_support" in r]
    steps = [r for r in rows if "localised" in r]
    named_lag_shupe = [r for r in strong if r.get("correct") and any(n in r["named"].split() for n in ("shupe", "thermal_lag"))]
    times = [r["run_time_s"] for r in rows]
    return {
        "naming correct at >= 0.25 sigma (incl. multi-effect)": "%s (%d/%d)" % (fmt(rate(strong, "correct"), 3), sum(1 for r in strong if r.get("correct")), len(strong)),
        "planted effects named, or listed as absorbed by the simulation (>= 0.25 sigma)": "%s (%d/%d)" % (
            fmt(rate(strong, "named_or_absorbed"), 3), sum(1 for r in strong if r.get("named_or_absorbed")),
            len([r for r in strong if "named_or_absorbed" in r])) if any("named_or_absorbed" in r for r in strong) else "-",
        "false discoveries on controls": "%s (%d/%d)" % (fmt(sum(1 for r in ctrl if r["verdict"] != "no_missing_physics") / max(1, len(ctrl)), 3),
                                                          sum(1 for r in ctrl if r["verdict"] != "no_missing_physics"), len(ctrl)),
        "false discoveries beside a correct lag or Shupe": "%d/%d" % (sum(1 for r in named_lag_shupe if r.get("wrong_extra")), len(named_lag_shupe)),
        "held-out excess removed, median / min (correctly named)": "%s / %s (n=%d)" % (fmt(float(np.median(excess)), 3), fmt(min(excess), 3), len(excess)) if excess else "-",
        "correctly named with < 50 % of the excess removed": "%d" % sum(1 for x in excess if x < 0.5),
        "  the same on every held-out sample (incl. outside the training support), median / min": "%s / %s (n=%d)" % (
            fmt(float(np.median(excess_all)), 3), fmt(min(excess_all), 3), len(excess_all)) if excess_all else "-",
        "  held-out samples outside the training support, median share": fmt(float(np.median(outside)), 3) if outside else "-",
        "steps reported unexplained and localised within 10 min": "%s (%d/%d)" % (fmt(rate(steps, "localised"), 3), sum(1 for r in steps if r["localised"]), len(steps)) if steps else "-",
        "run time per recording (s), median / max": "%s / %s" % (fmt(float(np.median(times)), 3), fmt(max(times), 3)) if times else "-",
    }


TARGETS = {"naming correct at >= 0.25 sigma (incl. multi-effect)": ">= 0.9", "false discoveries on controls": "<= 0.05",
           "planted effects named, or listed as absorbed by the simulation (>= 0.25 sigma)": "(issue 12, class 4)",
           "false discoveries beside a correct lag or Shupe": "0", "held-out excess removed, median / min (correctly named)": ">= 0.9 / >= 0.5",
           "correctly named with < 50 % of the excess removed": "0",
           "  the same on every held-out sample (incl. outside the training support), median / min": "(for reference)",
           "  held-out samples outside the training support, median share": "(for reference)", "steps reported unexplained and localised within 10 min": ">= 0.9",
           "run time per recording (s), median / max": "< 60 (<= 8 h at 1 Hz)"}


def both_generators_table(rows):
    by = {g: targets([r for r in rows if r["generator"] == g]) for g in ("simulator", "independent")}
    table = [{"target": k, "simulator (gyrosid simulate)": by["simulator"][k], "independent generator": by["independent"][k], "wanted": TARGETS[k]}
             for k in TARGETS]
    return ("## Both generators against the targets (issue 12)\n\n" +
            markdown_table(table, ["target", "simulator (gyrosid simulate)", "independent generator", "wanted"]) + "\n")


def independent_tables(rows):
    rows = [r for r in rows if r["generator"] == "independent"]
    if not rows:
        return ""
    cases = []
    for case in sorted({(r["group"], r["case"]) for r in rows}):
        rs = [r for r in rows if (r["group"], r["case"]) == case]
        ex = [r["heldout_excess_removed"] for r in rs if "heldout_excess_removed" in r]
        cases.append({"group": case[0], "case": case[1], "recordings": len(rs),
                      "correct": fmt(rate(rs, "correct"), 2) if any("correct" in r for r in rs) else "-",
                      "wrong extra": sum(r.get("wrong_extra", 0) for r in rs),
                      "excess removed (median)": fmt(float(np.median(ex)), 3) if ex else "-",
                      "localised": fmt(rate(rs, "localised"), 2) if any("localised" in r for r in rs) else "-",
                      "verdicts / named": "; ".join(sorted({r["verdict"] + (" (" + r["named"] + ")" if r["named"] else "") for r in rs})),
                      "time (s, max)": fmt(max(r["run_time_s"] for r in rs), 3)})
    return ("## Independent generator, case by case\n\n" + markdown_table(cases, ["group", "case", "recordings", "correct", "wrong extra",
            "excess removed (median)", "localised", "verdicts / named", "time (s, max)"]) + "\n")


def run_jobs(exp, jobs, workers, budget_min, partial=False):
    """Runs every job (explains already on disk are read back); stops starting new ones after the budget.
    Returns the rows, or when the budget ran out first None (or, with `partial`, the rows explained so far)."""
    start = time.time()
    rows, pending = [], list(jobs)

    def guarded(job):
        if budget_min and time.time() - start > 60.0 * budget_min and not os.path.exists(os.path.join(job["dir"], "explain", "explain.json")):
            return None
        return exp.do(job)

    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        for k, row in enumerate(pool.map(guarded, pending)):
            rows.append(row)
            if (k + 1) % 10 == 0 or k + 1 == len(pending):
                sys.stderr.write("  %d/%d recordings explained\n" % (k + 1, len(pending)))
    missing = sum(1 for r in rows if r is None)
    if missing:
        sys.stderr.write("budget of %s min used: %d recordings left; run again to continue\n" % (budget_min, missing))
        return None if not partial else [r for r in rows if r is not None]
    return rows


def first_seeds_first(jobs):
    """The jobs reordered so that every case's first seed comes before any case's second (stable otherwise):
    a sweep cut short by its budget still covers every case."""
    rank, seen = [], {}
    for j in jobs:
        key = (j["generator"], j["group"], j["case"])
        seen[key] = seen.get(key, 0) + 1
        rank.append(seen[key])
    return [j for _, _, j in sorted(zip(rank, range(len(jobs)), jobs), key=lambda x: (x[0], x[1]))]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--generators", default="simulator,independent", help="comma-separated: simulator, independent")
    ap.add_argument("--seeds", type=int, default=None, help="seeds per effect and magnitude (config: seeds, independent.seeds)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--budget-min", type=float, default=0.0, help="stop starting new recordings after this many minutes (0: no limit)")
    ap.add_argument("--force", action="store_true")
    ap.add_argument("--groups", default="", help="run only these case groups (comma-separated: effect, combination, confounded, outside, control)")
    ap.add_argument("--partial", action="store_true",
                    help="when the budget runs out, still write the summary from the recordings explained so far (counts show how many)")
    args = ap.parse_args()
    os.environ["GYROSID_THREADS"] = "1"  # one thread per explain, --jobs explains at a time
    exp = Experiment(args)
    generators = args.generators.split(",")
    out = os.path.abspath(args.out)
    jobs = []
    if "simulator" in generators:
        exp.simulation()
        jobs += jobs_of(exp.cfg, out, args.seeds or exp.cfg["seeds"])
    if "independent" in generators:
        jobs += independent_cases.jobs(exp.cfg["independent"], out, args.seeds or exp.cfg["independent"]["seeds"])
    if args.groups:
        jobs = [j for j in jobs if j["group"] in args.groups.split(",")]
    sys.stderr.write("%d recordings\n" % len(jobs))
    # Shapes first (shared, not thread-safe to create twice).
    for j in jobs:
        e = j.get("effect")
        if j["generator"] != "simulator":
            continue
        if e in ("shupe", "scale_factor_asymmetry"):
            exp.sensor_shape(j["trajectory"], **{("shupe" if e == "shupe" else "asymmetry"): 1.0})
        elif e == "thermal_lag":
            exp.sensor_shape(j["trajectory"], coil_tau=j["tau_s"])
    rows = run_jobs(exp, first_seeds_first(jobs), args.jobs, args.budget_min, args.partial)
    if rows is None:
        return
    cols = ["generator", "group", "case", "seed", "magnitude", "verdict", "named", "detected", "correct", "ambiguous", "wrong_extra",
            "param_rel_err", "param_covered", "effect_rel_err", "heldout_ratio", "heldout_excess_removed", "heldout_excess_removed_all",
            "heldout_outside_support", "heldout_samples", "localised", "unexplained",
            "run_time_s"]
    write_csv(os.path.join(args.out, "runs.csv"), rows, cols)
    planned = {g: sum(1 for j in jobs if j["generator"] == g) for g in ("simulator", "independent") if any(j["generator"] == g for j in jobs)}
    summarize(exp.cfg, rows, args.out, planned)
    sys.stderr.write("wrote %s/summary.md\n" % args.out)


if __name__ == "__main__":
    main()
