#!/usr/bin/python3
"""Why a joint RBF fit can lose to the sequential one (issue 10): the compare part's training recordings
fitted sequentially, jointly with the sequential nodes' weights moving (rbf_joint=weights, the default) and
jointly with every centre and width moving too (rbf_joint=nodes); each model compensates a noise-free probe
of the same sensor (trajectories/probe_grid.yaml: -40..80 C every 5 C, 0..100 deg/s) and is compared with
the truth where the flights live:

  * static error (deg/h rms) at -30..10 C, the long flight's temperatures (10 C at the start, 6.5 C/km
    to 6 km) at rate 0 - what its criterion of fit integrates for an hour;
  * turning error (deg/h rms) over 2..100 deg/s at every temperature;
  * M_ii (ppm) and the off-diagonal rms error (urad) against eq 3.72's planted sums.

    experiments/triad_misalignment/probe.py [--seeds 0,1,2,3] [--gyrosid build/gyrosid]

Reuses results/data/compare/ and results/models/compare/ (run.py compare), writes results/probe.md/.csv.
"""
import argparse
import os
import sys

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
from gyrosid_experiments import Runner, add_gyrosid_argument, fmt, load_json, markdown_table, read_recording, write_csv, write_text  # noqa: E402
from run import Experiment, OFF, first_order_m, matrix  # noqa: E402

ESTIMATIONS = {"sequential": ["--sequential"], "joint": ["--joint"], "joint_nodes": ["--joint", "--set", "rbf_joint=nodes"]}


def errors(comp, temp):
    """Static (-30..10 C) and turning rms errors, deg/h, over the three gyros."""
    static, turning = [], []
    for ax in "xyz":
        err = (comp["compensated_%s_dps" % ax] - comp["ref_rate_%s_dps" % ax]) * 3600.0
        rate = np.abs(comp["ref_rate_%s_dps" % ax])
        static.append(err[(rate < 0.01) & (temp >= -30) & (temp <= 10)])
        turning.append(err[(rate > 1) & (rate < 110)])
    rms = lambda parts: float(np.sqrt(np.mean(np.concatenate(parts) ** 2)))
    return rms(static), rms(turning)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(p)
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--seeds", default="0,1,2,3")
    args = p.parse_args()
    args.jobs, args.force = 1, False
    e = Experiment(args)
    run = Runner(args.gyrosid, args.out)
    c = e.cfg["compare"]
    rows = []
    for sname, sensor in c["sensors"].items():
        cfg_path = os.path.join(HERE, "..", "..", "configs", sensor[len("builtin:"):]) if sensor.startswith("builtin:") else e.sensor(sensor)
        planted, _ = first_order_m(yaml.safe_load(open(cfg_path))["misalignment_mrad"])
        probe = run.path("data", "probe", sname + ".csv")
        run.run(["simulate", "--noise-free", "--sensor", e.sensor(sensor), "--trajectory", os.path.join(HERE, "trajectories", "probe_grid.yaml"),
                 "--out", probe], probe)
        _, pc = read_recording(probe)
        for seed in [int(s) for s in args.seeds.split(",")]:
            for est, flags in ESTIMATIONS.items():
                tag = "compare/%s_rbf_%s" % (sname, est)
                fit = e.simulate_and_fit_tagged(sensor, c["trajectory"], seed, c["fits"]["rbf"] + flags, tag, "compare/" + sname)
                model = run.path("models", tag, "seed%d.json" % seed)
                comp = run.path("data", "probe", "%s_rbf_%s_seed%d.csv" % (sname, est, seed))
                run.run(["compensate", "--model", model, "--recording", probe, "--out", comp], comp)
                _, cc = read_recording(comp)
                static, turning = errors(cc, pc["temp_c"])
                m = matrix(fit)
                rows.append({"sensor": sname, "seed": seed, "estimation": est, "train_rms_dph": float(np.mean(fit["residual_rms_dph"])),
                             "static_m30_10C_dph": static, "turning_dph": turning,
                             "offdiag_err_urad": float(np.sqrt(np.nanmean([(m[i, j] - planted[i, j]) ** 2 for (i, j) in OFF])) * 1e6),
                             "M_ii_ppm": " ".join(fmt(v * 1e6, 4) for v in np.diag(m))})
                print(rows[-1], flush=True)
    cols = ["sensor", "seed", "estimation", "train_rms_dph", "static_m30_10C_dph", "turning_dph", "offdiag_err_urad", "M_ii_ppm"]
    write_csv(os.path.join(args.out, "probe.csv"), rows, cols)
    text = ("# Joint RBF against sequential, against the truth (probe.py)\n\nTraining `%s` (seed 0 noise-free, others 10 deg/h), "
            "RBF surfaces as in compare; each model compensates a noise-free probe of its sensor (-40..80 C every 5 C, "
            "0..100 deg/s). static: rms error at rate 0, -30..10 C (the long flight's); turning: rms over 2..100 deg/s, all "
            "temperatures; joint_nodes: rbf_joint=nodes (centres and widths free too).\n\n" % c["trajectory"])
    text += markdown_table(rows, cols)
    write_text(os.path.join(args.out, "probe.md"), text)
    print(text)


if __name__ == "__main__":
    main()
