#!/usr/bin/env python3
"""Every command on 10^6-10^7 samples: wall time and peak memory (issue 30, part 2).

    scale.py --gyrosid build/gyrosid --work /tmp/scale_work [--before OLD_GYROSID] [--full]

Recordings (written to --work, never committed):
  adis_1e6   ADIS16405 unit 1, gyro x: the static 100-Hz log of SMAC-Group/imudata (CC BY-NC-SA; read from
             ../shared/realdata with its reader tools/rdata.py), 10^6 samples, no thermometer (no temp_c column)
  sim_1e6    `gyrosid simulate` of the reference FOG along test_4x16 (four thermal cycles, 224 min) at 100 Hz
  sim_1e7    the same at 10^7 samples (744 Hz)
Runs, each under /usr/bin/time -v (wall time, peak resident set):
  explain on adis_1e6, sim_1e6 and sim_1e7 with the default --decimate auto; calibrate on sim_1e7 without
  options (the preset it chooses, --decimate auto); allan on sim_1e7 (one column held; its "reading ... done"
  line is the reader's time); compensate of sim_1e7 with the calibrated model (streamed).
--before OLD: the same explain on adis_1e6 (with a placeholder temp_c: the old reader needed one), calibrate on
  sim_1e6 and allan on sim_1e7 with a gyrosid built before this change.
--full: explain on adis_1e6 and sim_1e6 with --decimate none as well (the decimated verdict against the full one).
The table goes to --results/scale.md (default: results/ beside this script).
"""
import argparse
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import gyrosid_experiments as gx  # noqa: E402
from realdata import realdata  # noqa: E402


def adis_recording(path, with_temperature=False):
    """ADIS16405 unit 1's x gyro (deg/s, 100 Hz) as a single-gyro recording; the table at rest (ref 0)."""
    if os.path.exists(path):
        return
    sys.path.insert(0, os.path.join(realdata(), "tools"))
    import numpy as np
    import rdata
    obj = rdata.load(os.path.join(realdata(), "imudata", "adis_16405_imu1.rda"))["adis_16405_imu1"]
    nr, nc = [int(v) for v in rdata.attrs(obj)["dim"]["value"]]
    gyro = obj["value"].reshape(nc, nr).T[:, 0]
    t = np.arange(nr) / 100.0
    cols = [t, np.zeros(nr)] + ([np.full(nr, 25.0)] if with_temperature else []) + [gyro]
    names = "t_s,ref_rate_dps," + ("temp_c," if with_temperature else "") + "gyro_dps"
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sensor: ADIS16405 unit 1 gyro x (SMAC-Group/imudata, CC BY-NC-SA)\n# sample_rate_hz: 100\n")
        if with_temperature:
            f.write("# description: temp_c is a placeholder (not measured)\n")
        f.write(names + "\n")
        np.savetxt(f, np.column_stack(cols), fmt=["%.2f", "%g"] + (["%g"] if with_temperature else []) + ["%.10g"], delimiter=",")
    os.replace(tmp, path)


def timed(gyrosid, args, log):
    """Runs gyrosid under /usr/bin/time -v; returns (stdout, stderr, wall s, peak MB). Progress lines go to stderr."""
    result = subprocess.run(["/usr/bin/time", "-v", gyrosid] + [str(a) for a in args], capture_output=True, text=True)
    with open(log, "w") as f:
        f.write(result.stdout + "\n--- stderr ---\n" + result.stderr)
    if result.returncode != 0:
        raise RuntimeError("gyrosid %s failed; see %s" % (" ".join(map(str, args)), log))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", result.stderr).group(1)
    seconds = sum(float(p) * 60 ** i for i, p in enumerate(reversed(wall.split(":"))))
    peak_mb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", result.stderr).group(1)) / 1024.0
    return result.stdout, result.stderr, seconds, peak_mb


def reading_seconds(stderr):
    """The reader's own time from its progress line 'reading <file>...: done in X s' (absent under a second)."""
    m = re.search(r"^reading [^\n]*: done in ([0-9.]+) s", stderr, re.M)
    return float(m.group(1)) if m else ""


def summary_line(command, stdout):
    """What a run concluded: explain's verdict, calibrate's model line, allan's white noise, compensate's rms."""
    pattern = {"explain": r"^verdict: .*", "calibrate": r"^wrote .*", "allan": r"^noise model .*", "compensate": r"^wrote .*"}[command]
    m = re.search(pattern, stdout, re.M)
    return m.group(0).strip() if m else ""


# Issue 30's targets: (command, samples) -> (wall s, peak MB).
TARGETS = {("explain", "1e6"): (60, 1024), ("explain", "1e7"): (600, 2048), ("calibrate", "1e7"): (120, 2048)}


def target(row):
    """'<= 60 s, 1024 MB: pass' (or MISS, naming what missed) for a run the issue sets a target for; '' otherwise."""
    if row["build"] != "this" or "(" in row["recording"]:
        return ""
    t = TARGETS.get((row["command"], row["recording"].split("_")[-1]))
    if t is None:
        return ""
    if row["wall_s"] == "":
        return "MISS (failed)"
    missed = [what for what, value, limit in (("time", row["wall_s"], t[0]), ("memory", row["peak_mb"], t[1])) if value > limit]
    return "<= %d s, %d MB: %s" % (t[0], t[1], "MISS (" + ", ".join(missed) + ")" if missed else "pass")


def uptime():
    """The machine's load while measuring (the 2 cores are shared with other jobs)."""
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def decimation_line(stdout):
    m = re.search(r"^decimated: block means of (\d+) samples, interval (\S+) -> (\S+) s", stdout, re.M)
    return ("%s (%s -> %s s)" % m.groups()) if m else "none"


def write_results(a, gyrosid, rows, load_before):
    """scale.csv and scale.md under a.results, rewritten after every run (a partial table survives a stopped run)."""
    for r in rows:
        r["target"] = target(r)
    columns = ["build", "command", "recording", "decimation", "wall_s", "peak_mb", "reading_s", "target", "result"]
    gx.write_csv(os.path.join(a.results, "scale.csv"), rows, columns)
    text = ("# Every command on 10^6-10^7 samples\n\n`experiments/real_recordings/scale.py --gyrosid %s --work %s%s%s` (wall time and peak resident "
            "set from /usr/bin/time -v; reading_s from the reader's own progress line).\n\n" % (
                os.path.relpath(gyrosid), a.work, " --before " + a.before if a.before else "", " --full" if a.full else "")
            + ("" if not a.only else "Runs: %s.\n\n" % a.only))
    text += gx.markdown_table(rows, columns, ["build", "command", "recording", "decimation (b, interval)", "wall s", "peak MB", "reading s", "target", "result"])
    text += "\nMachine load (uptime) before the runs: `%s`; after: `%s`.\n" % (load_before, uptime())
    gx.write_text(os.path.join(a.results, "scale.md"), text)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    gx.add_gyrosid_argument(p)
    p.add_argument("--work", default="/tmp/gyrosid_scale", help="recordings and outputs (large; not committed)")
    p.add_argument("--results", default=os.path.join(HERE, "results"))
    p.add_argument("--before", help="a gyrosid built before the change, for the before column")
    p.add_argument("--full", action="store_true", help="also explain at the recorded rate (--decimate none)")
    p.add_argument("--only", help="comma-separated command:recording pairs to run (e.g. explain:sim_1e7); default all")
    a = p.parse_args()
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.results, exist_ok=True)
    w = lambda name: os.path.join(a.work, name)  # noqa: E731
    gyrosid = os.path.abspath(a.gyrosid)

    adis_recording(w("adis_1e6.csv"))
    for name, samples in (("sim_1e6", 1344000), ("sim_1e7", 10000000)):
        if not os.path.exists(w(name + ".csv")):
            subprocess.run([gyrosid, "--quiet", "simulate", "--trajectory", "builtin:trajectories/test_4x16.yaml", "--samples", str(samples),
                            "--seed", "3", "--out", w(name + ".csv")], check=True)

    runs = [
        ("explain", "adis_1e6", ["explain", "--recording", w("adis_1e6.csv"), "--out", w("explain_adis_1e6")]),
        ("explain", "sim_1e6", ["explain", "--recording", w("sim_1e6.csv"), "--out", w("explain_sim_1e6")]),
        ("calibrate", "sim_1e6", ["calibrate", "--recording", w("sim_1e6.csv"), "--out", w("calibrate_sim_1e6.json")]),
        ("calibrate", "sim_1e7", ["calibrate", "--recording", w("sim_1e7.csv"), "--out", w("calibrate_sim_1e7.json")]),
        ("allan", "sim_1e7", ["allan", "--recording", w("sim_1e7.csv"), "--subtract", "ref_rate_dps", "--out", w("allan_sim_1e7")]),
        ("compensate", "sim_1e7", ["compensate", "--model", w("calibrate_sim_1e7.json"), "--recording", w("sim_1e7.csv"), "--out", w("compensated_sim_1e7.csv")]),
        ("explain", "sim_1e7", ["explain", "--recording", w("sim_1e7.csv"), "--out", w("explain_sim_1e7")]),
    ]
    if a.full:
        runs += [("explain", "adis_1e6 (none)", ["explain", "--recording", w("adis_1e6.csv"), "--decimate", "none", "--out", w("explain_adis_1e6_none")]),
                 ("explain", "sim_1e6 (none)", ["explain", "--recording", w("sim_1e6.csv"), "--decimate", "none", "--out", w("explain_sim_1e6_none")])]
    rows = []
    load_before = uptime()
    only = set(a.only.split(",")) if a.only else None
    for command, recording, args in runs:
        if only is not None and "%s:%s" % (command, recording) not in only:
            continue
        log = w("%s_%s.log" % (command, recording.replace(" ", "_").replace("(", "").replace(")", "")))
        try:
            out, err, seconds, peak = timed(gyrosid, args, log)
        except RuntimeError as e:  # recorded, not hidden: the table says which run failed
            rows.append({"build": "this", "command": command, "recording": recording, "decimation": "", "wall_s": "", "peak_mb": "",
                         "reading_s": "", "result": "FAILED: %s" % e})
            continue
        rows.append({"build": "this", "command": command, "recording": recording, "decimation": decimation_line(out) if command in ("explain", "calibrate") else "",
                     "wall_s": seconds, "peak_mb": peak, "reading_s": reading_seconds(err), "result": summary_line(command, out)})
        print(rows[-1], flush=True)
        write_results(a, gyrosid, rows, load_before)
    if a.before:
        adis_recording(w("adis_1e6_temp.csv"), with_temperature=True)
        before = [("explain", "adis_1e6 (temp_c 25)", ["explain", "--recording", w("adis_1e6_temp.csv"), "--out", w("explain_adis_1e6_before")]),
                  ("calibrate", "sim_1e6", ["calibrate", "--recording", w("sim_1e6.csv"), "--out", w("calibrate_sim_1e6_before.json")]),
                  ("allan", "sim_1e7", ["allan", "--recording", w("sim_1e7.csv"), "--subtract", "ref_rate_dps", "--out", w("allan_sim_1e7_before")])]
        for command, recording, args in before:
            out, err, seconds, peak = timed(os.path.abspath(a.before), args, w("before_%s.log" % command))
            rows.append({"build": "before", "command": command, "recording": recording, "decimation": "", "wall_s": seconds, "peak_mb": peak,
                         "reading_s": "", "result": summary_line(command, out)})
            print(rows[-1], flush=True)
    write_results(a, gyrosid, rows, load_before)
    print("wrote", os.path.join(a.results, "scale.md"))


if __name__ == "__main__":
    main()
