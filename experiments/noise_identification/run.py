#!/usr/bin/env python3
"""Noise identification against known truth: a composite of quantization, white noise, flicker, rate random walk
and two Gauss-Markov processes drawn by an independent numpy generator (generator.py), identified by
`gyrosid allan` (its structure given, and chosen automatically) and by a GMWM-class reference (gmwm.py) on the
same records. Writes results/rows.csv and results/summary.md.

    experiments/noise_identification/run.py --seeds 100 [--gyrosid build/gyrosid] [--work /tmp/noise_id]
"""
import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, HERE)
import generator  # noqa: E402
import gmwm  # noqa: E402
from gyrosid_experiments import Runner, add_gyrosid_argument, fmt, markdown_table, write_csv, write_text  # noqa: E402

DT = 0.1           # 10 Hz
N = 1 << 20        # 29 h: the fit spans 0.1 s to 2.9 h, five decades, each term ruling somewhere
# deg/h-based units: Q (deg/h) s = arcsec, N (deg/h) sqrt(s), B deg/h, K (deg/h)/sqrt(s), GM (deg/h, s)
# Each term rules somewhere: Q at 0.1 s, N at 1 s, GM1 at 10 s, B at 50 s, GM2 at 600 s, K at the longest taus.
TRUTH = dict(Q=1.0, N=3.0, B=3.0, K=0.1, gauss_markov=((3.0, 5.0), (6.0, 300.0)))
STRUCTURE = ["Q", "N", "B", "K", "GM", "GM"]
# The quoted units gyrosid writes: N deg/sqrt(h) = /60, K (deg/h)/sqrt(h) = *60.
QUOTE = {"Q": 1.0, "N": 1.0 / 60.0, "B": 1.0, "K": 60.0, "GM1 sigma": 1.0, "GM1 tau": 1.0, "GM2 sigma": 1.0, "GM2 tau": 1.0}


def truth_quoted():
    t = {"Q": TRUTH["Q"], "N": TRUTH["N"], "B": TRUTH["B"], "K": TRUTH["K"]}
    for i, (s, tau) in enumerate(TRUTH["gauss_markov"], start=1):
        t["GM%d sigma" % i], t["GM%d tau" % i] = s, tau
    return {k: v * QUOTE[k] for k, v in t.items()}


def write_record(path, y):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sensor: composite noise, experiments/noise_identification/generator.py\n")
        f.write("# sample_rate_hz: %g\n" % (1.0 / DT))
        f.write("t_s,ref_rate_dps,temp_c,gyro_dps\n")
        t = np.arange(len(y)) * DT
        np.savetxt(f, np.column_stack([t, np.zeros(len(y)), np.full(len(y), 25.0), y / 3600.0]), delimiter=",",
                   fmt=["%.1f", "%d", "%d", "%.17g"])
    os.replace(tmp, path)


def matched_terms(terms):
    """gyrosid's terms with its Gauss-Markov pairs renamed after the true term nearest in log tau (a term whose
    variance sits at zero has no tau: it takes the true term the other one did not)."""
    out = [t for t in terms if not t["name"].startswith("GM")]
    fitted = []
    for t in terms:
        if t["name"].endswith(" sigma"):
            tau = next((u for u in terms if u["name"] == t["name"].replace("sigma", "tau")), None)
            fitted.append((t, tau))
    truth_taus = [tau for _, tau in TRUTH["gauss_markov"]]
    taken = set()
    for sig, tau in sorted(fitted, key=lambda st: st[1] is None):
        if tau is not None:
            k = min((i for i in range(len(truth_taus)) if i not in taken), key=lambda i: abs(np.log(tau["value"] / truth_taus[i])))
        else:
            k = next(i for i in range(len(truth_taus)) if i not in taken)
        taken.add(k)
        out.append(dict(sig, name="GM%d sigma" % (k + 1)))
        zero_tau = dict(name="", value=np.nan, sigma=np.nan, low=np.nan, high=np.nan)
        out.append(dict(tau if tau is not None else zero_tau, name="GM%d tau" % (k + 1)))
    return out


def ours(runner, rec, out, terms):
    seconds = runner.run(["allan", "--recording", rec, "--column", "gyro_dps", "--confidence", "0.95", "--terms", terms,
                          "--out", out], os.path.join(out, "allan.json"))
    with open(os.path.join(out, "allan.json")) as f:
        j = json.load(f)
    return j, seconds


def one_seed(runner, seed, work):
    y = generator.composite(N, DT, seed, Q=TRUTH["Q"], N=TRUTH["N"], B=TRUTH["B"], K=TRUTH["K"],
                            gauss_markov=TRUTH["gauss_markov"])
    rec = os.path.join(work, "rec_%d.csv" % seed)
    fixed_out, auto_out = runner.path("seed_%d" % seed, "fixed"), runner.path("seed_%d" % seed, "auto")
    if not (os.path.exists(os.path.join(fixed_out, "allan.json")) and os.path.exists(os.path.join(auto_out, "allan.json"))):
        write_record(rec, y)
    fixed, t_fixed = ours(runner, rec, fixed_out, "+".join(STRUCTURE))
    auto, t_auto = ours(runner, rec, auto_out, "auto")
    if os.path.exists(rec):
        os.remove(rec)
    start = time.time()
    ref, _ = gmwm.fit(y, DT, STRUCTURE)
    t_gmwm = time.time() - start
    row = {"seed": seed, "auto_model": auto["noise"]["model"], "fit_low_s": fixed["noise"]["fit_band_s"][0],
           "seconds_fixed": t_fixed, "seconds_gmwm": t_gmwm}
    for term in matched_terms(fixed["noise"]["terms"]):
        row["ours " + term["name"]] = term["value"]
        row["sigma " + term["name"]] = term["sigma"]
        row["low " + term["name"]] = term["low"]
        row["high " + term["name"]] = term["high"]
    for name, value in zip(gmwm.names(STRUCTURE), ref):
        row["gmwm " + name] = value * QUOTE[name]
    return row


def summary(rows):
    truth = truth_quoted()
    table = []
    for name, value in truth.items():
        ours_v = np.array([r["ours " + name] for r in rows])
        sig = np.array([r["sigma " + name] for r in rows])
        lo = np.array([r["low " + name] for r in rows])
        hi = np.array([r["high " + name] for r in rows])
        ref = np.array([r["gmwm " + name] for r in rows])
        z = (ours_v - value) / np.where(sig > 0, sig, np.nan)
        rmse, rmse_ref = np.sqrt(np.nanmean((ours_v - value) ** 2)), np.sqrt(np.mean((ref - value) ** 2))
        table.append({"parameter": name, "truth": fmt(value, 4), "mean": fmt(np.nanmean(ours_v), 4), "rmse": fmt(rmse, 3),
                      "rms z": fmt(np.sqrt(np.nanmean(z * z)), 3), "coverage 95 %": fmt(np.mean((lo <= value) & (value <= hi)), 3),
                      "not found": int(np.sum(np.isnan(ours_v))),
                      "GMWM mean": fmt(np.mean(ref), 4), "GMWM rmse": fmt(rmse_ref, 3), "rmse / GMWM": fmt(rmse / rmse_ref, 3)})
    return table


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(p)
    p.add_argument("--seeds", type=int, default=100)
    p.add_argument("--work", default="/tmp/noise_identification")
    p.add_argument("--results", default=os.path.join(HERE, "results"))
    p.add_argument("--force", action="store_true")
    a = p.parse_args()
    runner = Runner(a.gyrosid, a.work, a.force)
    rows = []
    for seed in range(1, a.seeds + 1):
        rows.append(one_seed(runner, seed, a.work))
        print("seed %d: auto %s, %.1f s (gyrosid, fixed) %.1f s (GMWM)" % (seed, rows[-1]["auto_model"], rows[-1]["seconds_fixed"],
                                                                         rows[-1]["seconds_gmwm"]), file=sys.stderr)
    os.makedirs(a.results, exist_ok=True)
    write_csv(os.path.join(a.results, "rows.csv"), rows, list(rows[0].keys()))
    table = summary(rows)
    models = {}
    for r in rows:
        models[r["auto_model"]] = models.get(r["auto_model"], 0) + 1
    text = ["# Noise identification against known truth", "",
            "%d records of %d samples at %g Hz (%.2f h) from generator.py: Q %g arcsec, N %g deg/sqrt(h), B %g deg/h, K %g (deg/h)/sqrt(h), "
            "Gauss-Markov (%g deg/h, %g s) and (%g deg/h, %g s). gyrosid with the structure given (`--terms %s`), 95 %% intervals; "
            "GMWM the reference in gmwm.py on the same records." % (
                len(rows), N, 1 / DT, N * DT / 3600, TRUTH["Q"], TRUTH["N"] / 60, TRUTH["B"], TRUTH["K"] * 60,
                TRUTH["gauss_markov"][0][0], TRUTH["gauss_markov"][0][1], TRUTH["gauss_markov"][1][0], TRUTH["gauss_markov"][1][1],
                "+".join(STRUCTURE)), "",
            markdown_table(table, list(table[0].keys())), "",
            "Structure chosen automatically (`--terms auto`): " + ", ".join("%s %d" % (k, v) for k, v in sorted(models.items(), key=lambda kv: -kv[1])),
            "", "Median time: gyrosid %.2f s a record (reading the CSV included), GMWM reference %.2f s." % (
                np.median([r["seconds_fixed"] for r in rows]), np.median([r["seconds_gmwm"] for r in rows])), ""]
    write_text(os.path.join(a.results, "summary.md"), "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
