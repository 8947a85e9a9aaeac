#!/usr/bin/env python3
"""A lot of real replicate units (issue 33): the six ADIS16405 static runs of SMAC-Group/imudata as a
noise-parameter lot. Does the lot's noise screen (src/lot/screen.cpp) hold its false-alarm rate on real units,
and does it find a unit with 3x the white noise?

Each unit goes through the project's own importer and noise identification (`gyrosid import --format kalibr`,
`gyrosid allan` per axis: experiments/real_recordings/noise.py's path, cached in --work). The white noise N of
each unit and axis is then screened as `lot screen` screens a unit's white noise, leave one out: the lot of the
other five units' ln N (mean m, sample sd s), z = (ln N_u - m) / (s sqrt(1 + 1/5)), two-sided p from Student's t
with 4 degrees of freedom (the screen's law since this stop) and, for comparison, from the normal (its law
before). A planted unit is each real unit with its rate noise tripled (N x 3, its recording otherwise the same).
The t tail here is scipy's, independent of gyrosid's stats::student_t_two_sided.

`lot learn` itself cannot take these logs: it calibrates the grey-box physics of every unit, and a static log
without a thermometer determines none of it. This is the noise half of a lot, measured on real units.

    /usr/bin/python3 experiments/production_lot/real_noise_lot.py [--gyrosid build/gyrosid] [--work /tmp/real_recordings]

Writes results/real_noise_lot.md and results/real_noise_lot.json.
"""
import argparse
import json
import os
import sys

import numpy as np
from scipy import stats

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, os.path.join(HERE, "..", "real_recordings"))
sys.path.insert(0, os.path.join(HERE, "..", "noise_identification"))
from gyrosid_experiments import add_gyrosid_argument, write_text  # noqa: E402
from noise import kalibr_to_recording, term  # noqa: E402
from realdata import run_timed  # noqa: E402

UNITS = range(1, 7)
ALPHAS = (0.01, 0.05)


def white_noise(gyrosid, work, unit, axis):
    """N (deg/sqrt(h)) of one unit's axis from `gyrosid allan` (cached)."""
    out = os.path.join(work, "adis%d_%s" % (unit, axis))
    if not os.path.exists(os.path.join(out, "allan.json")):
        rec = kalibr_to_recording(gyrosid, work, unit)
        run_timed([gyrosid, "allan", "--recording", rec, "--axis", axis, "--confidence", "0.95", "--out", out])
    with open(os.path.join(out, "allan.json")) as f:
        return term(json.load(f), "N")["value"]


def screen(log_n, u, shift=0.0):
    """Unit u (its ln N moved by `shift`) against the lot of the others: z and the t and normal p-values."""
    others = np.delete(log_n, u)
    n = len(others)
    z = (log_n[u] + shift - others.mean()) / (others.std(ddof=1) * np.sqrt(1.0 + 1.0 / n))
    return float(z), float(2.0 * stats.t.sf(abs(z), n - 1)), float(2.0 * stats.norm.sf(abs(z)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--work", default="/tmp/real_recordings")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows, clean, planted = [], [], []
    for axis in "xyz":
        n = np.array([white_noise(a.gyrosid, a.work, u, axis) for u in UNITS])
        log_n = np.log(n)
        for k, u in enumerate(UNITS):
            z, p_t, p_normal = screen(log_n, k)
            z3, p3_t, p3_normal = screen(log_n, k, np.log(3.0))
            rows.append({"axis": axis, "unit": u, "N": float(n[k]), "z": z, "p_t": p_t, "p_normal": p_normal, "z_3x": z3, "p_t_3x": p3_t, "p_normal_3x": p3_normal})
            clean.append((p_t, p_normal))
            planted.append((p3_t, p3_normal))
        print(axis, " ".join("%.3g" % x for x in n), "log sd %.3f" % log_n.std(ddof=1), file=sys.stderr)
    # The t law's own false-alarm rate of the normal's critical value with five units: what the change fixes.
    inflation = {al: float(2.0 * stats.t.sf(stats.norm.isf(al / 2.0), 4)) for al in ALPHAS}
    summary = {"rows": rows, "normal_critical_value_under_t4": inflation,
               "false_alarms": {str(al): {"t": sum(p < al for p, _ in clean), "normal": sum(q < al for _, q in clean), "of": len(clean)} for al in ALPHAS},
               "found_3x": {str(al): {"t": sum(p < al for p, _ in planted), "normal": sum(q < al for _, q in planted), "of": len(planted)} for al in ALPHAS}}
    lines = ["# A noise lot of six real ADIS16405 units (imudata), leave one out", "",
             "Command: `/usr/bin/python3 experiments/production_lot/real_noise_lot.py --gyrosid build/gyrosid`. White noise N from "
             "`gyrosid allan` per unit and axis; each unit screened against the other five as `lot screen` screens the noise "
             "(z = (ln N - m) / (s sqrt(1 + 1/5))); p from Student's t with 4 dof (the screen now) and the normal (before). "
             "Planted: the same unit with N x 3.", "",
             "| axis | unit | N deg/sqrt(h) | z | p (t, 4 dof) | p (normal) | z, N x 3 | p (t), N x 3 | p (normal), N x 3 |", "|---" * 9 + "|"]
    for r in rows:
        lines.append("| %s | %d | %.3f | %.2f | %.3g | %.3g | %.1f | %.2g | %.2g |" % (
            r["axis"], r["unit"], r["N"], r["z"], r["p_t"], r["p_normal"], r["z_3x"], r["p_t_3x"], r["p_normal_3x"]))
    lines.append("")
    for al in ALPHAS:
        fa, f3 = summary["false_alarms"][str(al)], summary["found_3x"][str(al)]
        lines.append("At alpha %g: clean units flagged %d/%d with t, %d/%d with the normal; 3x units found %d/%d with t, %d/%d with the normal. "
                     "The normal's critical value is t_4's %.1f %% point." % (al, fa["t"], fa["of"], fa["normal"], fa["of"], f3["t"], f3["of"],
                                                                         f3["normal"], f3["of"], 100 * inflation[al]))
    os.makedirs(a.results, exist_ok=True)
    write_text(os.path.join(a.results, "real_noise_lot.md"), "\n".join(lines) + "\n")
    write_text(os.path.join(a.results, "real_noise_lot.json"), json.dumps(summary, indent=1))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
