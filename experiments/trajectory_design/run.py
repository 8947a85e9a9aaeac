#!/usr/bin/env python3
"""Issue 9: do trajectories designed by `gyrosid design` beat the thesis's hand-made ones on noisy data?

    experiments/trajectory_design/run.py [--gyrosid build/gyrosid] [--out experiments/trajectory_design/results]
                                         [--max-minutes 25] [--force]

For every budget and design solver (config.yaml) it designs a trajectory, then simulates it and each thesis
trajectory with the sensor's noise for several seeds, calibrates every recording (gyrosid's best noisy
configuration; the grey-box fit the design assumed; the classical model on the soak) and scores it by the
criterion of fit on the short, medium and long flights (flight noise off, long after 1 h). It compares the
mean over seeds with the design's prediction and with the thesis's trajectories, and repeats a design on a
second sensor the design never saw. Intermediate files are cached under --out/work: a run stopped by
--max-minutes (or killed) resumes where it stopped. Writes results/*.csv, results/summary.md and the plots.
"""
import argparse
import math
import os
import sys
import time

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import add_gyrosid_argument, Runner, gnuplot, load_json, markdown_table, write_csv, write_text  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FLIGHTS = ["short", "medium", "long"]


class OutOfTime(Exception):
    pass


class Study:
    def __init__(self, args, cfg):
        self.cfg = cfg
        self.run = Runner(args.gyrosid, os.path.join(args.out, "work"), args.force)
        self.deadline = time.time() + 60.0 * args.max_minutes

    def gyrosid(self, argv, product):
        if not os.path.exists(product) and time.time() > self.deadline:
            raise OutOfTime()
        return self.run.run(argv, product)

    def sensor_path(self, sensor):
        return sensor if sensor.startswith("builtin:") else os.path.join(HERE, sensor)

    def design(self, tag, sensor, spec):
        """One design: spec = {solver, budget, criterion (optional; cof_minimax beats design.reference), envelope
        (optional; default design.envelope), set (optional {key: value}: design options, `--set key=value`)}."""
        c = self.cfg["design"]
        d = self.run.path(tag, "designs", design_name(spec), "x")[:-2]
        argv = ["design", "--budget-min", spec["budget"], "--model", spec.get("model", c["model"]), "--envelope", spec.get("envelope", c["envelope"]),
                "--sensor", sensor, "--solver", spec["solver"], "--seed", c["seed"], "--out", d]
        for key, value in sorted(spec.get("set", {}).items()):
            argv += ["--set", "%s=%s" % (key, value)]
        if spec.get("criterion"):
            argv += ["--criterion", spec["criterion"]]
        if spec.get("criterion") == "cof_minimax":
            # the trajectory to beat on every flight (a thesis trajectory), calibrated with its own model
            argv += ["--reference", self.cfg["thesis"][spec.get("reference", c["reference"])]]
            if spec.get("reference_model"):
                argv += ["--reference-model", spec["reference_model"]]
            if spec.get("reference_statistic"):
                argv += ["--reference-statistic", spec["reference_statistic"]]
        self.gyrosid(argv, os.path.join(d, "design.json"))
        return d

    def predictions(self, tag, sensor, trajectories, model):
        """Predicted criterion of fit of existing trajectories: {trajectory file: {flight: cof_m}}."""
        d = self.run.path(tag, "predicted_" + model, "x")[:-2]
        product = os.path.join(d, "evaluation.json")
        if os.path.exists(product) and any(t not in load_json(product)["trajectories"] for t in trajectories):
            os.remove(product)  # cached for fewer trajectories: evaluate them all again
        self.gyrosid(["design", "--evaluate"] + trajectories + ["--model", model, "--envelope", self.cfg["design"]["envelope"],
                                                                 "--sensor", sensor, "--out", d], os.path.join(d, "evaluation.json"))
        j = load_json(os.path.join(d, "evaluation.json"))["trajectories"]
        return {t: {f: j[t]["flights"][f]["cof_m"] for f in FLIGHTS} for t in trajectories}

    def score(self, tag, sensor, name, trajectory, seed, calibration, args):
        """Criterion of fit per flight of one calibration of one noisy recording."""
        rec = self.run.path(tag, "recordings", "%s_s%d.csv" % (name, seed))
        self.gyrosid(["simulate", "--sensor", sensor, "--trajectory", trajectory, "--seed", seed, "--out", rec], rec)
        model = self.run.path(tag, "models", "%s_s%d_%s.json" % (name, seed, calibration))
        self.gyrosid(["calibrate", "--recording", rec] + args + ["--out", model], model)
        out = {}
        for flight, extra in self.cfg["flights"].items():
            d = self.run.path(tag, "cof", "%s_s%d_%s_%s" % (name, seed, calibration, flight), "x")[:-2]
            self.gyrosid(["cof", "--model", model, "--sensor", sensor, "--trajectory", flight] + extra + ["--out", d],
                         os.path.join(d, "cof.json"))
            j = load_json(os.path.join(d, "cof.json"))
            out[flight] = j.get("error_after_1h_m", j["end_error_m"])
        return out

    def floor(self, tag, sensor, trajectories):
        """The information floor per trajectory file: {file: {flight: cof_noise_mean_m}} (E|S d|, averaged as the criterion is) of the smallest model nested in
        every calibration (a constant bias and scale factor), generalised least squares with the sensor's noise."""
        d = self.run.path(tag, "floor", "x")[:-2]
        zero = ["--set", "model.classical_bias_order=0", "--set", "model.classical_sf_temperature_order=0", "--set", "model.classical_sf_rate_order=0"]
        self.gyrosid(["design", "--evaluate"] + trajectories + ["--model", "classical"] + zero + ["--envelope", self.cfg["design"]["envelope"],
                                                                                                  "--sensor", sensor, "--out", d], os.path.join(d, "evaluation.json"))
        j = load_json(os.path.join(d, "evaluation.json"))["trajectories"]
        return {t: {f: j[t]["flights"][f]["cof_noise_mean_m"] for f in FLIGHTS} for t in trajectories}

    def rows(self, tag, sensor, designs, thesis_names, calibration=None, floor=False):
        """One row per (trajectory, calibration): predicted and achieved criterion of fit per flight.
        `designs` lists the designs ({solver, budget, criterion}); `calibration` (default design.calibration):
        best - the predictions are for gyrosid's best noisy calibration itself; assumed - for the design's own
        calibration.yaml (the hybrid given the sensor's noise model), best is fitted beside it. `floor`: add each
        trajectory's information floor (floor_<flight>_m)."""
        cfg = self.cfg
        trajectories = []  # (name, file, minutes, kind, predicted {flight: m} for the assumed calibration, solver info)
        for spec in designs:
            d = self.design(tag, sensor, spec)
            j = load_json(os.path.join(d, "design.json"))
            s = j["solver_summary"]
            info = {"objective": j["objective"], "design_s": s.get("time_s", s.get("seconds", "")), "criterion": spec.get("criterion", "cof"),
                    "evaluations": s.get("evaluations", s.get("iterations", "")), "termination": s.get("termination", "")}
            # A design for another model than the calibration's (design.model) predicts another calibration.
            own = spec.get("model", cfg["design"]["model"]) == cfg["design"]["model"]
            # (a design for part of the envelope predicts its own flights only)
            pred = {f: j["predicted"]["flights"][f]["cof_m"] for f in FLIGHTS if f in j["predicted"]["flights"]} if own else None
            info["design_model"] = spec.get("model", cfg["design"]["model"])
            trajectories.append((design_name(spec), os.path.join(d, "trajectory.yaml"), j["duration_min"], "design " + spec["solver"],
                                 pred, info, os.path.join(d, "calibration.yaml")))
        assumed_config = trajectories[0][6]  # the grey-box fit over the design domain (the same for every budget)
        files = [cfg["thesis"][n] for n in thesis_names]
        greybox = self.predictions(tag, sensor, files, cfg["design"]["model"])
        classical = self.predictions(tag, sensor, [cfg["thesis"][n] for n in thesis_names if n in cfg["classical_on"]], "classical") \
            if any(n in cfg["classical_on"] for n in thesis_names) else {}
        for n, f in zip(thesis_names, files):
            ev = load_json(os.path.join(self.run.out, tag, "predicted_" + cfg["design"]["model"], "evaluation.json"))["trajectories"][f]
            trajectories.append((n, f, ev["duration_min"], "thesis", greybox[f], {}, assumed_config))
        out = []
        # A design for gyrosid's best noisy calibration (design.model: hybrid, calibration: best) predicts that
        # calibration: no separate fit of the design's calibration.yaml.
        assumed_is_best = (calibration or cfg["design"].get("calibration")) == "best"
        floors = self.floor(tag, sensor, [t[1] for t in trajectories]) if floor else {}
        for name, path, minutes, kind, pred, info, assumed in trajectories:
            calibrations = [("best", cfg["calibrations"]["best"], pred)] if assumed_is_best else \
                [("best", cfg["calibrations"]["best"], None), ("assumed", ["--config", assumed], pred)]
            if name in cfg["classical_on"]:
                calibrations.append(("classical", cfg["calibrations"]["classical"], classical[path]))
            for cal, args, predicted in calibrations:
                sys.stderr.write("  %s %-16s %-9s" % (tag, name, cal))
                per_seed = [self.score(tag, sensor, name, path, seed, cal, args) for seed in cfg["seeds"]]
                row = {"trajectory": name, "kind": kind, "minutes": minutes, "calibration": cal}
                row.update(info)
                for f in FLIGHTS:
                    if path in floors:
                        row[f + "_floor_m"] = floors[path][f]
                    v = [s[f] for s in per_seed]
                    mean = sum(v) / len(v)
                    row[f + "_m"] = mean
                    row[f + "_sd_m"] = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
                    if predicted and f in predicted:
                        row[f + "_predicted_m"] = predicted[f]
                        row[f + "_pred_over_achieved"] = predicted[f] / mean
                sys.stderr.write(" " + "  ".join("%s %.3g m" % (f, row[f + "_m"]) for f in FLIGHTS) + "\n")
                out.append(row)
        return out


def design_name(spec):
    """solver_budget[_minimax][_vs_REFERENCE][_post|_mse][_ev][_ENVELOPE][_model]: the reference only when it is not
    design.reference; _post: the reference's posterior statistic (--reference-statistic posterior), _mse: the
    predicted mean squared criterion of fit of both (mse); _ev: model.network_prior=evidence; the envelope only when
    the spec gives one."""
    ev = spec.get("set", {}).get("model.network_prior") == "evidence"
    return "%s_%s%s%s%s%s%s%s" % (spec["solver"], spec["budget"], "_minimax" if spec.get("criterion") == "cof_minimax" else "",
                                  "_vs_" + spec["reference"].replace("classical_", "") if spec.get("reference") else "",
                                  {"posterior": "_post", "mse": "_mse"}.get(spec.get("reference_statistic"), ""),
                                  "_ev" if ev else "", "_" + spec["envelope"].replace(",", "_") if spec.get("envelope") else "",
                                  "_" + spec["model"] if spec.get("model") else "")


def fully_predicted(row):
    """A row with a prediction on every flight (a design for part of the envelope predicts only its own)."""
    return all(f + "_predicted_m" in row for f in FLIGHTS)


def find(rows, trajectory, calibration):
    return next(r for r in rows if r["trajectory"] == trajectory and r["calibration"] == calibration)


def targets(rows, cfg):
    """The issue's targets, each with its figures."""
    lines = []
    designs = [r for r in rows if r["kind"].startswith("design") and r["calibration"] == "best"]
    soak = find(rows, "classical_soak", "classical")
    le60 = [r for r in designs if r["minutes"] <= 60]
    winners = [r for r in le60 if all(r[f + "_m"] < soak[f + "_m"] for f in FLIGHTS)]
    best60 = min(le60, key=lambda r: max(r[f + "_m"] / soak[f + "_m"] for f in FLIGHTS))
    lines.append("1. A design of at most 60 min (best noisy calibration) beats the 8-h soak + classical model on every flight: %s. "
                 "%d of %d such designs do; the best (largest worst-flight factor) %s (%g min): %s." % (
                     "MET" if winners else "MISSED", len(winners), len(le60), best60["trajectory"], best60["minutes"],
                     ", ".join("%s %.3g m vs %.3g m (%.1fx)" % (f, best60[f + "_m"], soak[f + "_m"], soak[f + "_m"] / best60[f + "_m"]) for f in FLIGHTS)))
    dual = find(rows, "dual_scan", "best")
    for r in [r for r in designs if abs(r["minutes"] - dual["minutes"]) < 1.0]:
        ratios = [dual[f + "_m"] / r[f + "_m"] for f in FLIGHTS]
        lines.append("2. %s (%g min) against the dual scan (%g min), both with the best noisy calibration: %s on every flight by >= 1.5x: %s." % (
            r["trajectory"], r["minutes"], dual["minutes"], ", ".join("%s %.2fx" % (f, x) for f, x in zip(FLIGHTS, ratios)),
            "MET" if min(ratios) >= 1.5 else "MISSED"))
    assumed = [r for r in rows if fully_predicted(r)]
    worst = max(max(r[f + "_pred_over_achieved"], 1.0 / r[f + "_pred_over_achieved"]) for r in assumed for f in FLIGHTS)
    inside = sum(1 for r in assumed for f in FLIGHTS if 1 / 1.5 <= r[f + "_pred_over_achieved"] <= 1.5)
    lines.append("3. Predicted criterion of fit within 1.5x of the achieved mean (the calibration the prediction is for): %d of %d "
                 "(trajectory, flight) pairs; worst factor %.2f." % (inside, 3 * len(assumed), worst))
    t60 = [r for r in designs if 56 <= r["minutes"] <= 62]
    lines.append("4. Design solver time (design_s; shared machine) at 56-62 min budgets: %s (target < 120 s)." % ", ".join("%s %.1f s" % (r["trajectory"], float(r["design_s"])) for r in t60))
    return lines


def plots(out, rows, tag):
    best = [r for r in rows if r["calibration"] == "best"]
    for f in FLIGHTS:
        blocks, series = [], []
        for i, (label, sel) in enumerate([("design nlopt", lambda r: r["kind"] == "design nlopt"), ("design ipopt", lambda r: r["kind"] == "design ipopt"),
                                          ("thesis trajectories", lambda r: r["kind"] == "thesis")]):
            pts = sorted((r["minutes"], r[f + "_m"], r[f + "_sd_m"], r["trajectory"]) for r in best if sel(r))
            blocks.append("$d%d << EOD\n%s\nEOD\n" % (i, "\n".join("%g %g %g %s" % p for p in pts)))
            style = "linespoints" if label.startswith("design") else "points pt 7 ps 1.5"
            series.append("$d%d using 1:2:3 with yerrorbars notitle lc %d, $d%d using 1:2 with %s lc %d title '%s'" % (i, i + 1, i, style, i + 1, label))
            if label.startswith("thesis"):
                series.append("$d%d using 1:2:4 with labels offset 1,1 notitle" % i)
        soak = find(rows, "classical_soak", "classical")
        blocks.append("$c << EOD\n%g %g\nEOD\n" % (soak["minutes"], soak[f + "_m"]))
        series.append("$c using 1:2 with points pt 5 ps 1.5 lc 7 title '8-h soak, classical model'")
        gnuplot(os.path.join(out, "%spareto_%s.png" % (tag, f)), "".join(blocks) +
                "set logscale xy\nset grid\nset xlabel 'calibration time (min)'\nset ylabel 'criterion of fit (m), mean of seeds +- sd'\n"
                "set key top right\nset title 'Calibration minutes against criterion of fit, %s flight (best noisy calibration)'\nplot %s\n" % (f, ", ".join(series)))
    pts = [(r[f + "_predicted_m"], r[f + "_m"], f) for r in rows if fully_predicted(r) for f in FLIGHTS]
    blocks = "".join("$%s << EOD\n%s\nEOD\n" % (f, "\n".join("%g %g" % (p, a) for p, a, g in pts if g == f)) for f in FLIGHTS)
    gnuplot(os.path.join(out, "%spredicted_vs_achieved.png" % tag), blocks +
            "set logscale xy\nset grid\nset xlabel 'predicted criterion of fit (m)'\nset ylabel 'achieved mean (m)'\nset key top left\n"
            "set title 'Predicted against achieved criterion of fit (the calibration the prediction is for)'\n"
            "plot x title 'equal' lc 0, 1.5*x title 'x1.5' dt 2 lc 0, x/1.5 notitle dt 2 lc 0, "
            + ", ".join("$%s using 1:2 with points pt 7 title '%s'" % (f, f) for f in FLIGHTS) + "\n")


COLUMNS = ["trajectory", "kind", "minutes", "calibration"] + [f + s for f in FLIGHTS for s in ("_m", "_sd_m", "_predicted_m")]
FLOOR_COLUMNS = [f + "_floor_m" for f in FLIGHTS]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--config", default=os.path.join(HERE, "config.yaml"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--max-minutes", type=float, default=25.0, help="stop starting new work after this long (rerun to resume)")
    ap.add_argument("--force", action="store_true")
    args = ap.parse_args()
    cfg = yaml.safe_load(open(args.config))
    study = Study(args, cfg)
    try:
        sys.stderr.write("reference sensor\n")
        rows = study.rows("reference", cfg["sensor"], cfg["design"]["designs"], list(cfg["thesis"]))
        o = cfg.get("other_sensor")
        other = []
        if o:
            sys.stderr.write("second sensor (%s)\n" % o["sensor"])
            other = study.rows("other", study.sensor_path(o["sensor"]), o["designs"], o["thesis"], o.get("calibration"), o.get("floor", False))
    except OutOfTime:
        sys.stderr.write("stopped after --max-minutes %g; rerun to resume\n" % args.max_minutes)
        sys.exit(3)
    write_csv(os.path.join(args.out, "results.csv"), rows, COLUMNS + ["objective", "design_s", "evaluations", "termination"])
    if other:
        write_csv(os.path.join(args.out, "other_sensor.csv"), other, COLUMNS + (FLOOR_COLUMNS if any("short_floor_m" in r for r in other) else []))
    plots(args.out, rows, "")
    table_cols = ["trajectory", "minutes", "calibration", "short_m", "medium_m", "long_m", "short_predicted_m", "medium_predicted_m", "long_predicted_m"]
    solver_cols = ["trajectory", "minutes", "design_model", "criterion", "objective", "design_s", "evaluations", "short_m", "medium_m", "long_m"]
    text = ["# trajectory_design results\n", "Reference sensor, %d seeds, criterion of fit in metres (mean over seeds; long after 1 h).\n" % len(cfg["seeds"]),
            markdown_table(rows, table_cols), "\n## Targets\n"] + [l + "\n" for l in targets(rows, cfg)] + [
            "\n## NLopt against Ipopt (best noisy calibration)\n", markdown_table([r for r in rows if r["kind"].startswith("design") and r["calibration"] == "best"], solver_cols),
            ]
    if other:
        text += ["\n## Second sensor (%s)\n" % cfg["other_sensor"]["sensor"], markdown_table(other, table_cols)]
        if any(r["trajectory"] == "classical_soak" and r["calibration"] == "classical" for r in other):
            soak = find(other, "classical_soak", "classical")
            text += ["\nEach design (best noisy calibration) against this sensor's 8-h soak + classical model (factor = soak / design):\n\n"]
            text += ["- %s (%g min, calibration %s): %s%s\n" % (r["trajectory"], r["minutes"], r["calibration"],
                                                                  ", ".join("%s %.2fx" % (f, soak[f + "_m"] / r[f + "_m"]) for f in FLIGHTS),
                                                                  "" if all(r[f + "_m"] < soak[f + "_m"] for f in FLIGHTS) else " (loses a flight)")
                     for r in other if r["kind"].startswith("design") and r["calibration"] != "classical"]
        pred = [r for r in other if fully_predicted(r)]
        if pred:
            inside = sum(1 for r in pred for f in FLIGHTS if 1 / 1.5 <= r[f + "_pred_over_achieved"] <= 1.5)
            text += ["\nPredicted within 1.5x of the achieved mean (the calibration the prediction is for): %d of %d pairs; "
                     "predicted/achieved: %s.\n" % (inside, 3 * len(pred), "; ".join("%s %s %s" % (r["trajectory"], r["calibration"], "/".join(
                         "%.2f" % r[f + "_pred_over_achieved"] for f in FLIGHTS)) for r in pred))]
        fl = [r for r in other if "short_floor_m" in r and r["calibration"] != "classical"]
        if fl:
            text += ["\nInformation floor (criterion of fit, m, that the noise alone leaves when only a constant bias and scale factor "
                     "are estimated, by generalised least squares with the sensor's true noise - below every calibration "
                     "model's along that trajectory), against this sensor's soak + classical achieved:\n\n",
                     markdown_table([{"trajectory": r["trajectory"], "minutes": r["minutes"], **{f + "_floor_m": r[f + "_floor_m"] for f in FLIGHTS}}
                                     for r in fl if r["calibration"] == fl[0]["calibration"]],
                                    ["trajectory", "minutes"] + [f + "_floor_m" for f in FLIGHTS])]
    write_text(os.path.join(args.out, "summary.md"), "".join(text))
    sys.stdout.write("".join(text))


if __name__ == "__main__":
    main()
