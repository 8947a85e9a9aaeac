#!/usr/bin/python3
"""Solver comparison: every RBF solver (and the classical model) on the same training recordings.

    experiments/solver_comparison/run.py [--gyrosid build/gyrosid] [--out experiments/solver_comparison/results]
                                         [--only dual_11110] [--force]

Writes results.csv, results.md, thesis_sweep.csv and plots into --out; intermediate recordings, models and
surfaces stay under it, so an interrupted run resumes where it stopped.
"""
import argparse
import math
import os
import sys

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import Runner, add_gyrosid_argument, gnuplot, load_json, markdown_table, model_size, rate_error_dph, read_recording, set_args, write_csv, write_text  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def heldout_rms_dph(path):
    """RMS of compensated - reference rate over a compensated recording, deg/h."""
    _, cols = read_recording(path)
    d = rate_error_dph(cols, measured="compensated_dps")
    return math.sqrt(float((d * d).mean()))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--config", default=os.path.join(HERE, "config.yaml"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--only", help="run only this training set")
    ap.add_argument("--skip-thesis", action="store_true", help="leave out the thesis width sweep")
    ap.add_argument("--force", action="store_true", help="recompute everything")
    args = ap.parse_args()
    cfg = yaml.safe_load(open(args.config))
    run = Runner(args.gyrosid, args.out, args.force)
    surface_args = ["--temp-range", cfg["surface"]["temp_range"], "--rate-range", cfg["surface"]["rate_range"]]

    validation = run.path("data", "validation.csv")
    run.run(["simulate", "--sensor", cfg["sensor"], "--trajectory", cfg["validation"], "--noise-free",
             "--seed", cfg["seed"] + 1, "--out", validation], validation)

    def evaluate(train, noise, label, calibrate_args, extra=None):
        tag = "%s/%s" % (train["name"], noise)
        model = run.path("models", tag, label + ".json")
        seconds = run.run(["calibrate"] + calibrate_args + ["--out", model], model)
        surface_dir = run.path("surfaces", tag, label, "x")[:-2]
        run.run(["surface", "--model", model, "--sensor", cfg["sensor"], "--out", surface_dir] + surface_args,
                os.path.join(surface_dir, "surface.json"))
        comp = run.path("heldout", tag, label + ".csv")
        run.run(["compensate", "--model", model, "--recording", validation, "--out", comp], comp)
        m = load_json(model)
        s = load_json(os.path.join(surface_dir, "surface.json"))["difference"]
        summary = m["summary"]
        row = {"training": train["name"], "noise": noise, "solver": label,
               "nodes": model_size(summary),
               "time_s": summary.get("time_s", 0.0), "peak_rss_mb": summary.get("peak_rss_mb", ""),
               "termination": summary.get("termination", ""),
               "mean_dph": s["mean_dph"], "sigma_dph": s["sigma_dph"], "max_dph": s["max_dph"],
               "min_dph": s["min_dph"], "rms_dph": s["rms_dph"], "heldout_rms_dph": heldout_rms_dph(comp)}
        # Criterion of fit (issue 4): the position error the calibration leaves in a strapdown INS, noise-free
        # (thesis Table 5.4): end of the 50-s medium flight, and one hour into the long flight (beyond that
        # the free vertical channel dominates).
        for flight, key, field in (("medium", "cof_medium_m", "end_error_m"), ("long", "cof_long_1h_m", "error_after_1h_m")):
            if flight == "long" and extra:
                continue  # the thesis sweep: medium only
            cof_dir = run.path("cof", tag, label, flight, "x")[:-2]
            run.run(["cof", "--model", model, "--trajectory", flight, "--out", cof_dir], os.path.join(cof_dir, "cof.json"))
            row[key] = load_json(os.path.join(cof_dir, "cof.json"))[field]
        if extra:
            row.update(extra)
        sys.stderr.write("  %-12s %-12s %-12s nodes %5s  %7.2f s  surface rms %8.4g deg/h  held-out %8.4g deg/h%s\n" % (
            train["name"], noise, label, row["nodes"], row["time_s"], row["rms_dph"], row["heldout_rms_dph"],
            "" if seconds == 0 else "  (%.0f s)" % seconds))
        return row

    rows, sweep = [], []
    for train in cfg["training"]:
        if args.only and train["name"] != args.only:
            continue
        for noise in cfg["noise"]:
            rec = run.path("data", "train_%s_%s.csv" % (train["name"], noise))
            sim = ["simulate", "--sensor", cfg["sensor"], "--trajectory", train["trajectory"], "--seed", cfg["seed"], "--out", rec]
            if "samples" in train:
                sim += ["--samples", train["samples"]]
            if noise == "noise_free":
                sim.append("--noise-free")
            run.run(sim, rec)
            for s in cfg["solvers"]:
                opts = set_args(s["options"])
                rows.append(evaluate(train, noise, s["name"], ["--recording", rec, "--solver", s["solver"]] + opts))
            rows.append(evaluate(train, noise, "classical", ["--recording", rec, "--model", "classical"]))
            if not args.skip_thesis:
                for w in cfg["thesis"]["widths"]:
                    opts = ["--normalization", "units", "--set", "width=%s" % w] + set_args(cfg["thesis"]["options"])
                    sweep.append(evaluate(train, noise, "thesis_w%s" % w, ["--recording", rec, "--solver", "ols"] + opts,
                                          {"width": w}))

    columns = ["training", "noise", "solver", "nodes", "time_s", "peak_rss_mb", "mean_dph", "sigma_dph", "max_dph",
               "min_dph", "rms_dph", "heldout_rms_dph", "cof_medium_m", "cof_long_1h_m", "termination"]
    write_csv(os.path.join(args.out, "results.csv"), rows, columns)
    if sweep:
        write_csv(os.path.join(args.out, "thesis_sweep.csv"), sweep, ["width"] + columns)

    md = ["# Solver comparison\n",
          "Surface statistics are estimated minus true error over %s C x %s deg/s (deg/h); held-out is the RMS "
          "compensation error on the noise-free validation trajectory (deg/h); cof_medium_m and cof_long_1h_m are the "
          "criterion of fit (noise-free INS position error at the end of the 50-s medium flight and one hour into the "
          "long flight, m; `gyrosid cof`). Generated by `%s`.\n" % (
              cfg["surface"]["temp_range"], cfg["surface"]["rate_range"], " ".join(sys.argv))]
    for noise in cfg["noise"]:
        md.append("\n## %s\n\n" % noise)
        md.append(markdown_table([r for r in rows if r["noise"] == noise],
                                 ["training", "solver", "nodes", "time_s", "peak_rss_mb", "mean_dph", "sigma_dph",
                                  "max_dph", "min_dph", "rms_dph", "heldout_rms_dph", "cof_medium_m", "cof_long_1h_m"]))
    if sweep:
        md.append("\n## Thesis configuration (OLS, BIC, raw units), node scale swept (cf. Tables 5.2/5.3)\n\n")
        md.append(markdown_table(sweep, ["training", "noise", "width", "nodes", "time_s", "mean_dph", "sigma_dph",
                                         "max_dph", "min_dph", "rms_dph", "cof_medium_m"]))
    write_text(os.path.join(args.out, "results.md"), "".join(md))

    # Plots: accuracy against nodes per solver; the thesis sweep.
    for noise in cfg["noise"]:
        blocks, plots = [], []
        for i, s in enumerate([c["name"] for c in cfg["solvers"]]):
            pts = [(r["nodes"], r["rms_dph"]) for r in rows if r["noise"] == noise and r["solver"] == s]
            if not pts:
                continue
            blocks.append("$s%d << EOD\n%s\nEOD\n" % (i, "\n".join("%s %s" % p for p in pts)))
            plots.append("$s%d using 1:2 with points pt %d ps 1.5 title '%s'" % (i, 5 + i, s))
        if plots:
            gnuplot(os.path.join(args.out, "accuracy_vs_nodes_%s.png" % noise),
                    "".join(blocks) + "set logscale xy\nset grid\nset xlabel 'nodes'\nset ylabel 'surface rms error (deg/h)'\n"
                    "set title 'Accuracy against network size, %s (all training sets)'\nset key outside right\nplot %s\n" % (
                        noise, ", ".join(plots)))
    if sweep:
        blocks, plots = [], []
        for i, (t, n) in enumerate(sorted({(r["training"], r["noise"]) for r in sweep})):
            pts = sorted((r["width"], r["sigma_dph"]) for r in sweep if r["training"] == t and r["noise"] == n)
            blocks.append("$w%d << EOD\n%s\nEOD\n" % (i, "\n".join("%s %s" % p for p in pts)))
            plots.append("$w%d using 1:2 with linespoints title '%s, %s'" % (i, t, n))
        gnuplot(os.path.join(args.out, "thesis_width_sweep.png"),
                "".join(blocks) + "set logscale y\nset grid\nset xlabel 'node scale (raw units)'\nset ylabel 'sigma of surface error (deg/h)'\n"
                "set title 'Thesis configuration: OLS + BIC, width by trial'\nset key outside right\nplot %s\n" % ", ".join(plots))
    sys.stderr.write("wrote %s/results.md\n" % args.out)


if __name__ == "__main__":
    main()
