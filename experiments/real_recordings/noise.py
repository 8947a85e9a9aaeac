#!/usr/bin/env python3
"""Noise identification on public real recordings: the six ADIS16405 static runs (x, y, z) and the Xsens MTi-G
set of SMAC-Group/imudata (CC BY-NC-SA: read from ../shared/realdata, written only to --work, never committed).

Each log goes through the project's own importer (`gyrosid import --format kalibr`, from the EuRoC/Kalibr CSV
that ../shared/realdata/tools/convert_imudata.py writes), then `gyrosid allan --confidence 0.95` per axis (the
MTi-G also with --robust: its set holds outliers on purpose), timed with /usr/bin/time. Beside it, on the same
rates, the GMWM reference of ../noise_identification/gmwm.py with the structure gyrosid chose (without the
filter term F, which it does not have). Writes results/noise.md and results/noise.csv.

    experiments/real_recordings/noise.py [--gyrosid build/gyrosid] [--work /tmp/real_recordings] [--units 1,2,3,4,5,6]
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, os.path.join(HERE, "..", "noise_identification"))
import gmwm  # noqa: E402
from gyrosid_experiments import add_gyrosid_argument, fmt, markdown_table, write_csv, write_text  # noqa: E402
from realdata import realdata, run_timed  # noqa: E402

# ADIS16405 datasheet (Analog Devices, rev. B): angular random walk 2.0 deg/sqrt(h); in-run bias stability
# 0.007 deg/s = 25.2 deg/h (the Allan minimum).
DATASHEET = {"N": 2.0, "bias stability": 25.2}


def kalibr_to_recording(gyrosid, work, unit):
    """ADIS unit -> Kalibr CSV (EuRoC header, by the data set's own converter) -> gyrosid triad recording."""
    rec = os.path.join(work, "adis%d.csv" % unit)
    if os.path.exists(rec):
        return rec
    kalibr = os.path.join(work, "adis%d_kalibr.csv" % unit)
    subprocess.run([sys.executable, os.path.join(realdata(), "tools", "convert_imudata.py"),
                    os.path.join(realdata(), "imudata", "adis_16405_imu%d.rda" % unit), "adis_16405_imu%d" % unit, kalibr, "kalibr"],
                   check=True, capture_output=True)
    run_timed([gyrosid, "import", "--format", "kalibr", "--input", kalibr, "--stationary", "--out", rec])  # no thermometer: no temp_c
    os.remove(kalibr)
    return rec


def mtig_recording(work):
    rec = os.path.join(work, "mtig.csv")
    if not os.path.exists(rec):
        subprocess.run([sys.executable, os.path.join(realdata(), "tools", "convert_imudata.py"),
                        os.path.join(realdata(), "imudata", "cont.imu1.rda"), "cont.imu1", rec, "single"], check=True, capture_output=True)
    return rec


def read_columns(rec):
    """A gyrosid recording's columns by name (numpy: the '# key: value' lines skipped, the header named)."""
    with open(rec) as f:
        skip = 0
        for line in f:
            if not line.startswith("#"):
                break
            skip += 1
    return np.genfromtxt(rec, delimiter=",", names=True, skip_header=skip)


def read_curve(out):
    with open(os.path.join(out, "allan.json")) as f:
        j = json.load(f)
    with open(os.path.join(out, "allan.csv")) as f:
        curve = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    return j, curve


def misses(curve, band, model_adev):
    """Taus in the band where a model's deviation lies outside the data's interval: count, of, worst excess
    beyond the band's edge (relative)."""
    lo, hi = band
    count, total, worst = 0, 0, 0.0
    for p in curve:
        if not (lo * (1 - 1e-9) <= p["tau_s"] <= hi * (1 + 1e-9)):
            continue
        total += 1
        f = model_adev(p["tau_s"])
        if f < p["ci_low_dph"] or f > p["ci_high_dph"]:
            count += 1
            worst = max(worst, p["ci_low_dph"] / f - 1 if f < p["ci_low_dph"] else f / p["ci_high_dph"] - 1)
    return count, total, worst


def term(j, name):
    for t in j["noise"]["terms"]:
        if t["name"] == name:
            return t
    return None


def interval(t, digits=3):
    return "—" if t is None else "%s [%s, %s]" % (fmt(t["value"], digits), fmt(t["low"], 2), fmt(t["high"], 2))


def peer(rate_dph, dt, structure):
    """GMWM with gyrosid's structure (F dropped); its Allan deviation as a function of tau."""
    terms = [t for t in structure.split("+") if t in ("Q", "N", "B", "K", "GM")]
    theta, _ = gmwm.fit(rate_dph, dt, terms)
    return terms, theta, lambda tau: float(np.sqrt(2.0 * gmwm.model_wv(theta, np.array([tau]), terms)[0]))


def analyse(gyrosid, rec, column, out, rate_dph, dt, label, robust=False):
    # A triad recording's gyro is chosen by --axis (`allan` refuses --column gyro_x_dps on a triad).
    axis = re.fullmatch(r"gyro_([xyz])_dps", column)
    args = [gyrosid, "allan", "--recording", rec] + (["--axis", axis.group(1)] if axis else ["--column", column]) + ["--confidence", "0.95", "--out", out]
    seconds, peak_kb = run_timed(args + (["--robust"] if robust else []))
    j, curve = read_curve(out)
    band = j["noise"]["fit_band_s"]
    noise = j["noise"]
    n_miss, n_band, worst = misses(curve, band, lambda tau: next(p["fit_dph"] for p in curve if p["tau_s"] == tau))
    terms, theta, peer_adev = peer(rate_dph, dt, noise["model"])
    p_miss, _, p_worst = misses(curve, band, peer_adev)
    m = j["allan_minimum"]
    gm = ["%s deg/h, %s s" % (fmt(g["sigma_dph"], 3), fmt(g["tau_s"], 3)) for g in noise["gauss_markov"]]
    return {"recording": label, "model": noise["model"], "N deg/sqrt(h)": interval(term(j, "N")), "B deg/h": interval(term(j, "B")),
            "Gauss-Markov": "; ".join(gm) or "—", "fit from s": fmt(band[0], 2), "left out": "yes" if noise["left_out"] else "",
            "minimum deg/h [95 %]": "%s [%s, %s]" % (fmt(m["adev_dph"], 3), fmt(m["ci_low_dph"], 3), fmt(m["ci_high_dph"], 3)),
            "fit at minimum": fmt(m["fit_dph"], 3), "min in band": "yes" if m["ci_low_dph"] <= m["fit_dph"] <= m["ci_high_dph"] else "NO",
            "outside band": "%d/%d" % (n_miss, n_band), "worst beyond": "%s %%" % fmt(100 * worst, 2) if n_miss else "",
            "GMWM outside": "%d/%d" % (p_miss, n_band), "GMWM worst": "%s %%" % fmt(100 * p_worst, 2) if p_miss else "",
            "time s": fmt(seconds, 3), "peak MB": fmt(peak_kb / 1024.0, 3)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--work", default="/tmp/real_recordings")
    ap.add_argument("--units", default="1,2,3,4,5,6")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows = []
    for unit in [int(u) for u in a.units.split(",")]:
        rec = kalibr_to_recording(a.gyrosid, a.work, unit)
        cols = read_columns(rec)
        dt = float(np.median(np.diff(cols["t_s"])))
        for axis in "xyz":
            column = "gyro_%s_dps" % axis
            rows.append(analyse(a.gyrosid, rec, column, os.path.join(a.work, "adis%d_%s" % (unit, axis)), cols[column] * 3600.0, dt,
                                "ADIS16405 #%d %s" % (unit, axis)))
            print(rows[-1], file=sys.stderr)
    rec = mtig_recording(a.work)
    cols = read_columns(rec)
    for robust in (False, True):
        rows.append(analyse(a.gyrosid, rec, "gyro_dps", os.path.join(a.work, "mtig" + ("_robust" if robust else "")), cols["gyro_dps"] * 3600.0,
                            0.01, "MTi-G x" + (" (--robust)" if robust else ""), robust))
        print(rows[-1], file=sys.stderr)
    os.makedirs(a.results, exist_ok=True)
    write_csv(os.path.join(a.results, "noise.csv"), rows, list(rows[0].keys()))
    columns = ["recording", "model", "N deg/sqrt(h)", "B deg/h", "Gauss-Markov", "fit from s", "minimum deg/h [95 %]", "fit at minimum",
               "min in band", "outside band", "worst beyond", "GMWM outside", "GMWM worst", "time s", "peak MB"]
    text = ["# Noise identification on real recordings", "",
            "`gyrosid allan --confidence 0.95` on each axis (95 %% intervals). ADIS16405 datasheet: N %g deg/sqrt(h), in-run bias "
            "stability %g deg/h (the Allan minimum). 'outside band': display taus inside the fit band where the fitted deviation lies "
            "outside the data's 95 %% interval, and the worst distance beyond the interval's edge; the same for the GMWM reference "
            "with gyrosid's structure on the same rates. Time and peak memory of the whole `allan` command (reading 10^6 rows "
            "included), /usr/bin/time." % (DATASHEET["N"], DATASHEET["bias stability"]), "",
            markdown_table(rows, columns), ""]
    write_text(os.path.join(a.results, "noise.md"), "\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
