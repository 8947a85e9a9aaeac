#!/usr/bin/env python3
"""Sensor C': the staircase's information limit, measured on the same fits.

Sensor C's staircase holds the rate at 13 levels, w = 25 k deg/s (k = -6..6). Its ripple term cos(2 pi w / 55)
takes there the values of cos(2 pi w / P') with P' = 1375 / 30 = 45.83 deg/s: 25 k / 55 = 5 k / 11 and
25 k / P' = 6 k / 11 add up to the integer k. Sensor C' is sensor C with P' for 55. Its staircase recordings are
sensor C's to the last bits of the CSV (the largest difference is printed), so every method, gyrosid's or a
peer's, returns one fit for both sensors, while the two sensors' truths between the levels differ. If d is the
rms difference of the two truths over an evaluation set, a fit's rms errors e_C and e_C' there satisfy
e_C + e_C' >= d (triangle inequality), so no fit has both below d / 2: the staircase cannot tell the two
sensors apart, and which prior wins between its levels depends on which sensor was there.

This script scores the fits run.py cached for sensor C's staircase (models/c/staircase/<noise>/seed<n>/*.json,
compensated again here on both sensors' noise-free held-out trajectory and (T, omega) grid) and fits the peers
(peers.py, the same settings as run.py) on the same recordings, scored on both. It writes a Markdown table.

    counterfactual_c.py --gyrosid build/gyrosid --results <run.py's --out> --out results/counterfactual_c.md
"""
import argparse
import glob
import json
import os
import subprocess
import sys

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, HERE)
import generator_c  # noqa: E402
from gyrosid_experiments import Runner, add_gyrosid_argument, read_recording, write_text  # noqa: E402

ALIAS_PERIOD_DPS = 1375.0 / 30.0  # the ripple period sensor C's staircase levels cannot tell from 55 deg/s
SENSORS = ("C", "C'")
SETS = ("heldout", "grid")


def rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def truths(cfg, results, work):
    """{(sensor, set): path} of the noise-free evaluation recordings: sensor C's from run.py's cache, C''s made here."""
    c = cfg["sensor_c"]
    paths = {("C", "heldout"): os.path.join(results, "data", "c", "heldout.csv"),
             ("C", "grid"): os.path.join(results, "data", "c", "grid.csv"),
             ("C'", "heldout"): os.path.join(work, "heldout_alias.csv"),
             ("C'", "grid"): os.path.join(work, "grid_alias.csv")}
    for s in SETS:
        if not os.path.exists(paths[("C", s)]):
            raise SystemExit("%s: not found - run run.py --part sensor_c with --out %s first" % (paths[("C", s)], results))
    generator_c.generate(paths[("C'", "heldout")], c["heldout"], 0.0, seed=999, noise_free=True,
                         ripple_period_dps=ALIAS_PERIOD_DPS)
    generator_c.write_grid(paths[("C'", "grid")], c["grid"]["temp_c"], c["grid"]["rate_dps"], ALIAS_PERIOD_DPS)
    return paths


def same_training(rec, noise, seed, work):
    """Largest |gyro_C' - gyro_C| (deg/h) of a staircase recording regenerated as sensor C' (same seed, noise)."""
    alias = os.path.join(work, "train_alias.csv")
    generator_c.generate(alias, "staircase", noise["white_dph"], noise.get("gm_sigma_dph", 0.0), noise.get("gm_tau_s", 0.0),
                         seed, ripple_period_dps=ALIAS_PERIOD_DPS)
    _, a = read_recording(alias)
    _, b = read_recording(rec)
    return float(np.max(np.abs(a["gyro_dps"] - b["gyro_dps"]))) * 3600.0


def gyrosid_scores(run, model, paths, tag):
    """rms (deg/h) of compensated - reference for a gyrosid model on each truth."""
    out = {}
    for key, path in paths.items():
        product = run.path("compensated", tag, "%s_%s.csv" % (key[1], "alias" if key[0] == "C'" else "c"))
        run.run(["compensate", "--model", model, "--recording", path, "--out", product], product)
        _, c = read_recording(product)
        out[key] = rms((c["compensated_dps"] - c["ref_rate_dps"]) * 3600.0)
    return out


def peer_scores(cfg, rec, seed, paths, product):
    """{peer: {(sensor, set): rms}}: peers.py fitted once on the recording, scored on all four truths."""
    if not os.path.exists(product):
        p = cfg["peers"]
        args = ["--train", rec, "--out", product, "--gp-subset", p["gp_subset"], "--krr-subset", p["krr_subset"], "--seed", seed]
        for path in paths.values():
            args += ["--eval", path]
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
        subprocess.run([sys.executable, os.path.join(HERE, "peers.py")] + [str(a) for a in args], check=True, env=env,
                       stderr=subprocess.DEVNULL)
    info = json.load(open(product))
    return {peer: {key: info[peer]["scores"][os.path.basename(path)]["rms_dph"] for key, path in paths.items()}
            for peer in ("gp", "krr")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--config", default=os.path.join(HERE, "config.yaml"))
    ap.add_argument("--results", required=True, help="run.py's --out: its sensor-C staircase recordings and models")
    ap.add_argument("--methods", default="hybrid,bayes,ols", help="gyrosid methods of run.py's config to score")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "counterfactual_c.md"))
    a = ap.parse_args()
    cfg = yaml.safe_load(open(a.config))
    results = os.path.abspath(a.results)
    run = Runner(a.gyrosid, os.path.join(results, "counterfactual_c"))
    paths = truths(cfg, results, run.out)
    difference = {}
    for s in SETS:
        _, c1 = read_recording(paths[("C", s)])
        _, c2 = read_recording(paths[("C'", s)])
        difference[s] = rms((c1["gyro_dps"] - c2["gyro_dps"]) * 3600.0)
    noises = {n["name"]: n for n in cfg["sensor_c"]["noises"]}
    methods = a.methods.split(",")
    rows, largest = [], 0.0
    for rec in sorted(glob.glob(os.path.join(results, "data", "c", "staircase", "*", "seed*.csv"))):
        noise = os.path.basename(os.path.dirname(rec))
        seed = int(os.path.basename(rec)[4:-4])
        largest = max(largest, same_training(rec, noises[noise], seed, run.out))
        scores = {}
        for m in methods:
            model = os.path.join(results, "models", "c", "staircase", noise, "seed%d" % seed, m + ".json")
            if os.path.exists(model):
                scores[m] = gyrosid_scores(run, model, paths, "%s/seed%d/%s" % (noise, seed, m))
        sys.stderr.write("%s seed %d: gyrosid scored; fitting the peers\n" % (noise, seed))
        scores.update(peer_scores(cfg, rec, seed, paths, run.path("peers", noise, "seed%d.json" % seed)))
        rows.append((noise, seed, scores))
    write_table(a.out, rows, difference, largest, methods + ["gp", "krr"], a)


def write_table(path, rows, difference, largest, methods, a):
    bound = {e: difference[e] / 2 for e in SETS}
    lines = ["# Sensor C': one staircase, two sensors", "",
             "Generated by `experiments/noisy_calibration/counterfactual_c.py --results %s --methods %s` (gyrosid: %s)." % (
                 a.results, a.methods, a.gyrosid), "",
             "Sensor C' is sensor C with the ripple's period %.4g deg/s for 55: at the staircase's levels the two laws "
             "agree, so the staircase recordings are the same (largest difference of a regenerated recording %.2g deg/h) "
             "and every fit below is one fit scored against two truths. The truths differ by %.2f deg/h rms on the "
             "held-out trajectory and %.2f on the grid: no fit can be below half that, %.2f / %.2f deg/h, on both "
             "sensors." % (ALIAS_PERIOD_DPS, largest, difference["heldout"], difference["grid"], bound["heldout"],
                            bound["grid"]), "",
             "rms error (deg/h) on each sensor's truth, and the worse of the two over that bound; the best per recording "
             "in bold.", "",
             "| recording | method | held-out C | held-out C' | worse / bound | grid C | grid C' | worse / bound |",
             "|---|---|---|---|---|---|---|---|"]
    columns = [(s, e) for e in SETS for s in SENSORS + ("worst",)]
    wins = {(m, c): 0 for m in methods for c in columns}
    for noise, seed, scores in rows:
        for m in scores:
            for e in SETS:
                scores[m][("worst", e)] = max(scores[m][(s, e)] for s in SENSORS) / bound[e]
        best = {c: min(v[c] for v in scores.values()) for c in columns}
        for m in [m for m in methods if m in scores]:
            cells = []
            for c in columns:
                text = "%.2f" % scores[m][c]
                cells.append("**%s**" % text if scores[m][c] == best[c] else text)
                wins[(m, c)] += scores[m][c] == best[c]
            lines.append("| %s seed %d | %s | %s |" % (noise, seed, m, " | ".join(cells)))
    lines += ["", "Recordings on which a method is the best of those scored (of %d):" % len(rows), "",
              "| method | held-out C | held-out C' | the worse of the two | grid C | grid C' | the worse of the two |",
              "|---|---|---|---|---|---|---|"]
    for m in methods:
        lines.append("| %s | %s |" % (m, " | ".join(str(wins[(m, c)]) for c in columns)))
    write_text(path, "\n".join(lines) + "\n")
    sys.stderr.write("%s written\n" % path)


if __name__ == "__main__":
    main()
