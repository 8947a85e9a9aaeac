#!/usr/bin/python3
"""Run docs/tutorial.md: every ```sh block, in order, in one bash with -e, in a scratch folder - then check that
each step wrote its files and that the numbers are those of a calibration that worked.

    docs/run_tutorial.py --gyrosid build/gyrosid [--work DIR] [--images docs/img]

The test Docs.Tutorial runs it on every build, so the page's commands cannot go stale. --images copies the
two plots the page shows into that folder (how docs/img/tutorial_*.png are made).
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
PAGE = os.path.join(HERE, "tutorial.md")

# Each step's output files, relative to the tutorial's folder (build/tutorial under the scratch folder).
OUTPUTS = ["tvc_gyro_x.csv", "tvc_gyro_x_first_burst.csv", "burst_x.csv", "allan/allan.json", "allan/allan.png",
           "model.json", "compensated_x.csv", "gyro_x.yaml", "cof/cof.json", "cof/error_growth.png",
           "one_temperature.json", "cof_one_temperature/cof.json"]
IMAGES = {"allan/allan.png": "tutorial_allan.png", "cof/error_growth.png": "tutorial_cof_error_growth.png"}


def sh_blocks(page):
    """The bodies of the page's ```sh fenced blocks, in order."""
    with open(page) as f:
        return re.findall(r"^```sh\n(.*?)^```$", f.read(), flags=re.S | re.M)


def rms_dph(path, column):
    """rms of column - ref_rate_dps over a recording, in deg/h."""
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    i, k = rows[0].index(column), rows[0].index("ref_rate_dps")
    errors = [float(r[i]) - float(r[k]) for r in rows[1:]]
    return math.sqrt(sum(e * e for e in errors) / len(errors)) * 3600.0


def check(folder):
    """Every output exists; the numbers are sane. Returns the failures."""
    failures = ["missing: " + name for name in OUTPUTS if not os.path.isfile(os.path.join(folder, name))]
    if failures:
        return failures
    allan = json.load(open(os.path.join(folder, "allan/allan.json")))
    arw = allan["coefficients"]["arw_deg_rt_h"]
    per_sample_dph = allan["coefficients"]["white_dph_at_1hz"] / math.sqrt(allan["sample_interval_s"])
    raw = rms_dph(os.path.join(folder, "compensated_x.csv"), "gyro_dps")
    compensated = rms_dph(os.path.join(folder, "compensated_x.csv"), "compensated_dps")
    cof = json.load(open(os.path.join(folder, "cof/cof.json")))
    one = json.load(open(os.path.join(folder, "cof_one_temperature/cof.json")))
    print("angle random walk %.4g deg/sqrt(h); rms error raw %.1f, compensated %.1f deg/h (noise per sample %.1f);"
          " short flight %.4g m (one temperature %.4g m, uncompensated %.4g m)"
          % (arw, raw, compensated, per_sample_dph, cof["end_error_m"], one["end_error_m"], cof["uncompensated_end_error_m"]))
    if not 0.05 < arw < 2.0:
        failures.append("angle random walk %g deg/sqrt(h) is not a MEMS gyro's (0.05..2)" % arw)
    if not compensated < raw / 10:
        failures.append("compensation left %g of %g deg/h" % (compensated, raw))
    if not 0.7 < compensated / per_sample_dph < 1.3:
        failures.append("compensated rms %g deg/h is not the per-sample noise %g deg/h" % (compensated, per_sample_dph))
    if not cof["end_error_m"] < one["end_error_m"] < cof["uncompensated_end_error_m"]:
        failures.append("criterion of fit not ordered: full %g, one temperature %g, uncompensated %g m"
                        % (cof["end_error_m"], one["end_error_m"], cof["uncompensated_end_error_m"]))
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gyrosid", required=True, help="the built gyrosid executable")
    ap.add_argument("--work", help="scratch folder (default: a temporary one, removed afterwards)")
    ap.add_argument("--images", help="copy the page's plots here")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="gyrosid-tutorial-")
    os.makedirs(work, exist_ok=True)
    script = os.path.join(work, "tutorial.sh")
    with open(script, "w") as f:
        f.write("set -euo pipefail\n" + "\n".join(sh_blocks(PAGE)))
    env = dict(os.environ, REPO=REPO, GYROSID_QUIET="1",
               PATH=os.path.dirname(os.path.abspath(args.gyrosid)) + os.pathsep + os.environ.get("PATH", ""))
    run = subprocess.run(["bash", script], cwd=work, env=env)
    folder = os.path.join(work, "build", "tutorial")
    failures = ["the page's commands failed (exit %d)" % run.returncode] if run.returncode else check(folder)
    if args.images and not failures:
        for name, image in IMAGES.items():
            shutil.copyfile(os.path.join(folder, name), os.path.join(args.images, image))
    if not args.work and not failures:
        shutil.rmtree(work)
    for failure in failures:
        print("FAIL: " + failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
