#!/usr/bin/env python3
"""The tables and power curves of real_noise.py's runs: one CSV per binary (real_noise.py --tag T writes
<out>/T.csv), each summarised beside the known-form detector's floor (its oracle_power column).

    real_noise_report.py --csv /tmp/real_noise/ada527d.csv [--csv OLD.csv] --md results/real_noise.md --png results/real_noise_power.png
"""
import argparse
import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib"))
from gyrosid_experiments import gnuplot, markdown_table, write_text  # noqa: E402

EFFECTS = ["bias_step", "warmup_transient", "aging_trend", "auxiliary_channel"]


def load(path):
    rows = list(csv.DictReader(open(path)))
    for r in rows:
        r["magnitude"] = float(r["magnitude"])
        r["right"] = r["right"] == "True"
        r["oracle_power"] = float(r["oracle_power"]) if r.get("oracle_power") not in (None, "", "None") else None
        r["run_time_s"] = float(r["run_time_s"])
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--csv", action="append", required=True, help="a run's CSV (repeat: one per binary; its name is its tag)")
    p.add_argument("--md", required=True, help="markdown tables to write")
    p.add_argument("--png", required=True, help="power curves to write")
    a = p.parse_args()
    runs = {os.path.splitext(os.path.basename(c))[0].replace("real_noise_", ""): load(c) for c in a.csv}
    md = ["# Effects planted in real noise\n\n",
          "`real_noise.py` on the ADIS16405 (6 units x 3 gyros) and MTi-G static logs of ../shared/realdata; magnitude in sigma, "
          "the log's per-sample (100-Hz) noise; oracle: the known-form detector at 5 % false discoveries (the floor).\n\n"]
    table, blocks, cmds = [], [], []
    for tag, rows in runs.items():
        for effect in EFFECTS:
            mags = sorted({r["magnitude"] for r in rows if r["effect"] == effect})
            if not mags:
                continue
            pts, floor = [], []
            for m in mags:
                g = [r for r in rows if r["effect"] == effect and r["magnitude"] == m]
                o = [r["oracle_power"] for r in g if r["oracle_power"] is not None]
                table.append({"binary": tag, "effect": effect, "sigma": "%g" % m, "right": "%d/%d" % (sum(r["right"] for r in g), len(g)),
                              "oracle": "%.2f" % np.mean(o) if o else "-", "misses": " ".join(r["log"] for r in g if not r["right"])})
                pts.append((m, np.mean([r["right"] for r in g])))
                if o:
                    floor.append((m, np.mean(o)))
            k = len(blocks)
            blocks.append("$d%d << EOD\n%s\nEOD\n" % (k, "\n".join("%g %g" % q for q in pts)))
            cmds.append("$d%d using 1:2 with linespoints lw 2 title '%s %s'" % (k, effect, tag))
            if floor and tag == list(runs)[0]:
                blocks.append("$d%d << EOD\n%s\nEOD\n" % (k + 1, "\n".join("%g %g" % q for q in floor)))
                cmds.append("$d%d using 1:2 with lines dt 2 lw 1 title '%s oracle'" % (k + 1, effect))
        controls = [r for r in rows if r["effect"] == "control"]
        if controls:
            table.append({"binary": tag, "effect": "control", "sigma": "0", "right": "%d/%d" % (sum(r["right"] for r in controls), len(controls)),
                          "oracle": "", "misses": " ".join("%s (%s)" % (r["log"], r["named"] or r["unexplained"]) for r in controls if not r["right"])})
        times = sorted(r["run_time_s"] for r in rows)
        md.append("%s: %d recordings, explain's run time median %.1f s, max %.1f s.\n\n" % (tag, len(rows), times[len(times) // 2], times[-1]))
    md.append(markdown_table(table, ["binary", "effect", "sigma", "right", "oracle", "misses"],
                             ["binary", "effect", "magnitude (sigma)", "named or localised", "oracle power", "missed on"]))
    md.append("\n![power](%s)\n" % os.path.basename(a.png))
    write_text(a.md, "".join(md))
    gnuplot(a.png, "".join(blocks) + "set logscale x\nset grid\nset key outside right\nset xlabel 'planted rms / per-sample noise'\n"
            "set ylabel 'fraction named or localised'\nset yrange [-0.05:1.05]\nset title 'explain on effects planted in real static logs'\nplot %s\n" % ", ".join(cmds))


if __name__ == "__main__":
    main()
