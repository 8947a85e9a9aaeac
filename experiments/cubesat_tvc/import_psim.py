#!/usr/bin/python3
"""Importer: the PAN CubeSat thermal-vacuum cooling log (../shared/realdata/psim, see its SOURCES.md) to
gyrosid recordings, one single-gyro recording per axis.

    experiments/cubesat_tvc/import_psim.py [--source <ancestor>/shared/realdata/psim/MATLAB/sensor_models/TVCtest3_7_20.csv]
                                           [--out experiments/cubesat_tvc/data]

Conversions (each one stated in the recordings' metadata):
  t_s           (time (ms) - first) / 1000
  gyro_dps      gyro<axis> rad/s * 180/pi
  ref_rate_dps  0: the satellite is static in the chamber; the Earth-rate projection on the axis is constant
                and unknown, so it is part of the constant bias
  temp_c        25 + (raw - 65536) / 256: the raw uint16 read as the LSM6DSM OUT_TEMP register - UNVERIFIED
                (SOURCES.md); it is monotone in the raw count, so the temperature effects found are real up to
                this scale
  mag_{x,y,z}_ut  mag1<axis> [T] * 1e6
The two spikes the authors' script removes (gyro x <= -0.08 rad/s) are dropped from every axis's recording.
Also written: <axis>_first_burst.csv, the first 5-s burst alone - a 'calibration' at one temperature for
`gyrosid explain --baseline`.
"""
import argparse
import csv
import hashlib
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
SOURCE = os.path.join("shared", "realdata", "psim", "MATLAB", "sensor_models", "TVCtest3_7_20.csv")


def default_source():
    """The log under the first ancestor of the repository that holds shared/realdata (a checkout at /work/main
    or a worktree at /work/wt/<name> both find /work/shared)."""
    d = os.path.dirname(ROOT)
    while True:
        if os.path.exists(os.path.join(d, SOURCE)):
            return os.path.join(d, SOURCE)
        if os.path.dirname(d) == d:
            return os.path.join(os.path.dirname(ROOT), SOURCE)
        d = os.path.dirname(d)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--source", default=default_source())
    ap.add_argument("--out", default=os.path.join(HERE, "data"))
    args = ap.parse_args()
    with open(args.source, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    rows = []
    with open(args.source, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        expected = ["time (ms)", "mag1x [T]", "mag1y [T]", "mag1z [T]", "gyrox rad/s", "gyroy rad/s", "gyroz rad/s", "temp"]
        if [h.strip() for h in header] != expected:
            raise SystemExit("%s: unexpected header %s (expected %s)" % (args.source, header, expected))
        for line, r in enumerate(reader, start=2):
            try:
                rows.append([float(v) for v in r])
            except ValueError as e:
                raise SystemExit("%s:%d: %s" % (args.source, line, e))
    kept = [r for r in rows if r[4] > -0.08]
    t0 = kept[0][0]
    os.makedirs(args.out, exist_ok=True)
    for axis, col in (("x", 4), ("y", 5), ("z", 6)):
        meta = ["# format: gyrosid-recording/1\n",
                "# sensor: PAN CubeSat ETU ADCS gyro (probably ST LSM6DSM), axis %s\n" % axis,
                "# description: thermal-vacuum cold test 2020-03-07, satellite static, chamber cooling; imported by "
                "experiments/cubesat_tvc/import_psim.py from %s (sha256 %s); %d spike rows dropped\n"
                % (os.path.basename(args.source), digest, len(rows) - len(kept)),
                "# temperature: 25 + (raw - 65536)/256 C, the LSM6DSM OUT_TEMP conversion - unverified\n",
                "# reference: 0 deg/s (static; the Earth-rate projection is part of the constant bias)\n"]
        lines = []
        for r in kept:
            lines.append("%.3f,0,%.6f,%.9g,%.6g,%.6g,%.6g\n" % ((r[0] - t0) / 1000.0, 25.0 + (r[7] - 65536.0) / 256.0,
                                                             math.degrees(r[col]), r[1] * 1e6, r[2] * 1e6, r[3] * 1e6))
        head = "t_s,ref_rate_dps,temp_c,gyro_dps,mag_x_ut,mag_y_ut,mag_z_ut\n"
        for name, body in (("%s.csv" % axis, lines), ("%s_first_burst.csv" % axis, lines[:250])):
            path = os.path.join(args.out, "tvc_gyro_" + name)
            with open(path + ".tmp", "w") as f:
                f.writelines(meta + [head] + body)
            os.replace(path + ".tmp", path)
    print("wrote %d samples per axis (%d spikes dropped) into %s" % (len(kept), len(rows) - len(kept), args.out))


if __name__ == "__main__":
    main()
