#!/usr/bin/python3
"""Reproduce du Plessis (2013) Table 5.4 - classical against RBF compensation scored by the criterion of
fit - and its sensitivity studies (node scale: Tables 5.5-5.7; start temperature: 5.8/5.9; thermal delay:
5.10/5.11). Noise-free, as the thesis's tables.

    experiments/thesis_table_5_4/run.py [--gyrosid build/gyrosid] [--out experiments/thesis_table_5_4/results]
                                        [--paper papers/du_plessis_2013] [--quick]

Writes tables (CSV, Markdown) and plots under --out and the write-up with the thesis's figures beside ours
into --paper/README.md. --quick skips the sweeps.
"""
import argparse
import os
import sys

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import add_gyrosid_argument, Runner, fmt, gnuplot, load_json, markdown_table, model_size, write_csv, write_text  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--config", default=os.path.join(HERE, "config.yaml"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--paper", default=os.path.join(ROOT, "papers", "du_plessis_2013"))
    ap.add_argument("--quick", action="store_true", help="Table 5.4 only, no sweeps")
    ap.add_argument("--force", action="store_true")
    args = ap.parse_args()
    cfg = yaml.safe_load(open(args.config))
    run = Runner(args.gyrosid, args.out, args.force)

    def recording(name):
        t = cfg["training"][name]
        rec = run.path("data", name + ".csv")
        sim = ["simulate", "--sensor", cfg["sensor"], "--trajectory", t["trajectory"], "--noise-free", "--seed", cfg["seed"], "--out", rec]
        if "samples" in t:
            sim += ["--samples", t["samples"]]
        run.run(sim, rec)
        return rec

    def model(label, training, extra):
        path = run.path("models", label + ".json")
        run.run(["calibrate", "--recording", recording(training)] + extra + ["--out", path], path)
        return path

    def cof(model_path, label, trajectory, start=cfg["start_temp_c"], delay=0, probe="coil"):
        out = run.path("cof", label, "%s_T%s_d%s_%s" % (trajectory, start, delay, probe), "x")[:-2]
        run.run(["cof", "--model", model_path, "--sensor", cfg["sensor"], "--trajectory", trajectory, "--start-temp-c", start,
                 "--thermal-delay-s", delay, "--temperature-probe", probe, "--out", out], os.path.join(out, "cof.json"))
        j = load_json(os.path.join(out, "cof.json"))
        # Long flights are scored after 1 h (thesis s5.3.3), short and medium at their end.
        j["score_m"] = j.get("error_after_1h_m", j["end_error_m"])
        return j

    sys.stderr.write("Table 5.4: models and criterion of fit from %s C\n" % cfg["start_temp_c"])
    models = {label: model(label, m["training"], m["args"]) for label, m in cfg["models"].items()}
    models["none"], models["truth"] = "none", "truth"
    table = []
    for traj in cfg["trajectories"]:
        row = {"trajectory": traj}
        for label, path in models.items():
            j = cof(path, label, traj)
            row[label + "_m"] = j["score_m"]
            row["duration_s"] = j["duration_s"]
        row["ratio_thesis_settings"] = row["classical_m"] / row["rbf_thesis_m"]
        row["ratio_best"] = row["classical_m"] / row["rbf_best_m"]
        th = cfg["thesis_table_5_4"][traj]
        row["thesis_classical_m"], row["thesis_rbf_m"] = th["classical_m"], th["rbf_m"]
        row["thesis_ratio"] = th["classical_m"] / th["rbf_m"]
        table.append(row)
        sys.stderr.write("  %-6s classical %10.4g m  rbf(thesis) %10.4g m  rbf(best) %10.4g m  ratio %8.4g / %8.4g\n" % (
            traj, row["classical_m"], row["rbf_thesis_m"], row["rbf_best_m"], row["ratio_thesis_settings"], row["ratio_best"]))
    cols = ["trajectory", "duration_s", "none_m", "classical_m", "rbf_thesis_m", "rbf_best_m", "truth_m", "ratio_thesis_settings",
            "ratio_best", "thesis_classical_m", "thesis_rbf_m", "thesis_ratio"]
    write_csv(os.path.join(args.out, "table_5_4.csv"), table, cols)

    sweeps = {}
    if not args.quick:
        sys.stderr.write("Tables 5.8-5.11: start temperature and thermal delay\n")
        rows = []
        for traj in cfg["trajectories"]:
            for start in cfg["start_temperatures_c"]:
                for case in cfg["delay_cases"]:
                    delay, probe = case["thermal_delay_s"], case["probe"]
                    r = {"trajectory": traj, "start_temp_c": start, "thermal_delay_s": delay, "probe": probe}
                    for label in ["classical", "rbf_thesis", "rbf_best"]:
                        r[label + "_m"] = cof(models[label], label, traj, start, delay, probe)["score_m"]
                    r["ratio_best"] = r["classical_m"] / r["rbf_best_m"]
                    rows.append(r)
        write_csv(os.path.join(args.out, "start_temperature_delay.csv"), rows, list(rows[0].keys()))
        sweeps["temperature"] = rows
        sys.stderr.write("Tables 5.5-5.7: node scale\n")
        rows = []
        for training in cfg["width_sweep"]["training"]:
            for w in cfg["width_sweep"]["widths"]:
                label = "w%s_%s" % (w, training)
                path = model(label, training, ["--solver", "ols", "--normalization", "units", "--set", "width=%s" % w,
                                               "--set", "criterion=bic", "--set", "candidates=0"])
                r = {"training": training, "width": w, "nodes": model_size(load_json(path)["summary"])}
                for traj in cfg["trajectories"]:
                    r[traj + "_m"] = cof(path, label, traj)["score_m"]
                rows.append(r)
        write_csv(os.path.join(args.out, "width_sweep.csv"), rows, list(rows[0].keys()))
        sweeps["width"] = rows
        for traj in cfg["trajectories"]:
            blocks, plots = [], []
            for i, training in enumerate(cfg["width_sweep"]["training"]):
                pts = [(r["width"], r[traj + "_m"]) for r in rows if r["training"] == training]
                blocks.append("$d%d << EOD\n%s\nEOD\n" % (i, "\n".join("%s %s" % p for p in pts)))
                plots.append("$d%d using 1:2 with linespoints title '%s'" % (i, training))
            gnuplot(os.path.join(args.out, "width_sweep_%s.png" % traj), "".join(blocks) +
                    "set logscale y\nset grid\nset xlabel 'node scale (raw units)'\nset ylabel 'criterion of fit (m)'\n"
                    "set title 'CoF against node scale, %s flight (cf. thesis figs 5.15-5.17)'\nplot %s\n" % (traj, ", ".join(plots)))
        sys.stderr.write("How rbf_best was found: candidate configurations on dual_11110\n")
        rows = []
        for label, extra in list(cfg["search"].items()) + [("rbf_noise_free (rbf_best)", None)]:
            path = models["rbf_best"] if extra is None else model("search_" + label, "dual_11110", extra)
            m = load_json(path)["summary"]
            r = {"configuration": label, "nodes": model_size(m), "fit_time_s": m["time_s"]}
            for traj in cfg["trajectories"]:
                j = cof(path, "rbf_best" if extra is None else "search_" + label, traj)
                r[traj + "_m"] = j["score_m"]
                r[traj + "_ratio"] = table_row(table, traj)["classical_m"] / j["score_m"]
            rows.append(r)
        write_csv(os.path.join(args.out, "search.csv"), rows, list(rows[0].keys()))
        sweeps["search"] = rows

    write_paper(args, cfg, table, sweeps)
    sys.stderr.write("wrote %s/README.md\n" % args.paper)


def table_row(table, trajectory):
    return next(r for r in table if r["trajectory"] == trajectory)


def write_paper(args, cfg, table, sweeps):
    os.makedirs(args.paper, exist_ok=True)
    cmd = "experiments/thesis_table_5_4/run.py" + (" --quick" if args.quick else "")
    worst = min(r["ratio_best"] for r in table)
    md = ["# du Plessis (2013), *An Alternative Gyroscope Calibration Methodology* - Table 5.4 and its sensitivity studies\n\n",
          "Regenerate everything (from the repository root, after `scripts/setup.sh build`): `%s` "
          "(about 10 minutes on two cores; intermediate results are cached under `experiments/thesis_table_5_4/results/`, "
          "`--force` recomputes).\n\n" % cmd,
          "All runs are noise-free, as the thesis's tables. The sensor is gyrosid's reference open-loop FOG (bias about "
          "-15 deg/h, cubic in temperature; scale-factor surface on the thesis's grid with synthetic values shaped after "
          "its figures, `configs/sensors/open_loop_fog.yaml`). The flights are gyrosid's built-ins shaped after appendix C "
          "(the thesis's 6-DOF data are not published), rates clipped to +-100 deg/s, temperature from altitude by the "
          "standard lapse rate from %s C. Short and medium flights are scored at their end, the 2-h flight after 1 h "
          "(s5.3.3).\n\n" % cfg["start_temp_c"],
          "Models: *classical* - bias cubic in T, scale factor of order 6 in rate and 2 in T, least squares on the "
          "8-h classical soak (s5.3.2); *RBF, thesis settings* - OLS with BIC on raw deg/s and deg C, node scale 17.5, "
          "all 1111 samples of the dual scan as candidates; *RBF, best* - `configs/calibration/rbf_noise_free.yaml`: OLS "
          "without ridge on the 11,110-sample dual scan, 3000 space-filling candidates of width 0.2 (inputs normalised to "
          "[-1, 1]) and a collinearity threshold of 1e-14, so that the network interpolates (section *How the best RBF "
          "was found* below).\n\n",
          "## Table 5.4 - criterion of fit (m)\n\n",
          markdown_table(table, ["trajectory", "none_m", "classical_m", "rbf_thesis_m", "rbf_best_m", "truth_m",
                                 "ratio_thesis_settings", "ratio_best", "thesis_classical_m", "thesis_rbf_m", "thesis_ratio"],
                         ["flight", "uncompensated", "classical", "RBF (thesis settings)", "RBF (best)", "perfect",
                          "classical / RBF thesis", "classical / RBF best", "thesis: classical", "thesis: RBF", "thesis: ratio"]),
          "\nThe thesis's numbers come from its text, whose extraction lost zeros and minus signs (its Table 5.4 reads "
          "\"1 seconds m.8 m 5 seconds m.19 m 1 hour m (5.12 ) 226 m (.2 )\"); they are the corrected figures of "
          "DESIGN.md: short 1.24 m against about 0.008 m, medium 1.47 m against about 0.02 m, long after 1 h \"roughly "
          "equivalent to a drift of 5 degrees\" (5 x 111 km) against 226 m. Absolute values differ from ours because "
          "neither the sensor's grid values nor the flights are the thesis's; the ratio classical/RBF is the comparable "
          "quantity. With the thesis's own RBF settings gyrosid reproduces its finding (two orders of magnitude); with "
          "the best configuration the ratio is at least %.0f on every flight.\n" % worst]
    if "temperature" in sweeps:
        md += ["\n## Tables 5.8-5.11 - start temperature and thermal delay (m)\n\n",
               markdown_table(sweeps["temperature"], ["trajectory", "start_temp_c", "thermal_delay_s", "probe", "classical_m",
                                                       "rbf_thesis_m", "rbf_best_m", "ratio_best"]),
               "\nThe thesis's Tables 5.8-5.11 did not survive the text extraction (their cells are empty or 'x'); its text "
               "says both methods perform consistently over start temperatures, that the 5-min delay makes a small "
               "difference, and that the compensation must be given \"the exact temperature of the sensor\". Rows with "
               "probe *coil* are that case: the gyro's own probe reads the delayed coil temperature, and the short and "
               "medium flights stay at their start temperature. Rows with probe *air* give the compensation the outside "
               "temperature instead: the delay then costs both methods alike and the RBF's advantage disappears on the "
               "flights that climb. The thesis's calibrated range was -20..60 C; gyrosid's reference sensor and "
               "trajectories cover -60..80 C, so no cell is invalid here.\n"]
        coil = [r for r in sweeps["temperature"] if r["probe"] == "coil"]
        below = ["%s from %s C%s (%.0f)" % (r["trajectory"], r["start_temp_c"], ", delay %s s" % r["thermal_delay_s"] if r["thermal_delay_s"] else "",
                                          r["ratio_best"]) for r in coil if r["ratio_best"] < 1000]
        md += ["\nWith the coil probe the best ratio ranges from %.0f to %.0f; " % (min(r["ratio_best"] for r in coil), max(r["ratio_best"] for r in coil)),
               ("it falls below 1000 for: %s. Near 20 C two things meet: the classical model is at its best on one of its "
                "soak plateaus (20 C), and the RBF's surface error is largest between the sensor grid's 20 and 25 C rows, "
                "where the true surface bends most (`gyrosid surface --temp-range 15,25` gives an rms of 0.0062 deg/h "
                "against 0.0038 for 5..15 C).\n" % "; ".join(below)) if below else
               "it stays above 1000 everywhere.\n"]
    if "width" in sweeps:
        md += ["\n## Tables 5.5-5.7 - criterion of fit against node scale (m)\n\n",
               markdown_table(sweeps["width"], ["training", "width", "nodes"] + [t + "_m" for t in cfg["trajectories"]]),
               "\nThe thesis's tables are lost in the extraction; its figures 5.15-5.17 show the same shape: small scales are "
               "worst (the network needs more nodes than Orr's toolbox gave it; here OLS stops at its cap of 500), the "
               "error falls to a minimum around 15-20 and rises slowly after. The denser trajectory does not help at "
               "1111 samples.\n\n"
               + "".join("![%s](../../experiments/thesis_table_5_4/results/width_sweep_%s.png)\n" % (t, t) for t in cfg["trajectories"])]
    if "search" in sweeps:
        md += ["\n## How the best RBF was found\n\n",
               "Candidate configurations on the 11,110-sample dual scan, scored by the same criterion of fit; the ratio is "
               "classical / configuration.\n\n",
               markdown_table(sweeps["search"], ["configuration", "nodes", "fit_time_s"] +
                              [t + k for t in cfg["trajectories"] for k in ("_m", "_ratio")]),
               "\nOn noise-free data the criterion of fit rewards interpolation: what limits OLS with its defaults is the "
               "ridge (Orr's re-estimated lambda) and the collinearity threshold, which stop the selection at a few hundred "
               "nodes. Without the ridge, with a threshold of 1e-14 on the squared residual norm of a candidate and enough "
               "candidates, forward selection keeps adding nearly dependent Gaussians and the surface error falls about "
               "thirtyfold; the joint optimisation of `ceres` (60 nodes) is far from that. On noisy data the same setting "
               "learns the noise: use `rbf_noisy.yaml` there (see experiments/solver_comparison).\n"]
    write_text(os.path.join(args.paper, "README.md"), "".join(md))


if __name__ == "__main__":
    main()
