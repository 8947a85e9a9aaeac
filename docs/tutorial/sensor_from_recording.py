#!/usr/bin/python3
"""Write a gyro sensor config (the `--sensor` of `gyrosid cof` and `simulate`) from what a static recording and
its Allan deviation measured: the bias as a straight line in temperature and the white noise.

    docs/tutorial/sensor_from_recording.py RECORDING.csv ALLAN.json OUT.yaml [--reference-c 20]

The recording is cut into its bursts (gaps longer than 1 s); each burst gives one mean of gyro_dps - ref_rate_dps
and one mean temperature, and the line bias(T) = b0 + b1 (T - T_ref) is fitted to those means by least squares
(an estimate independent of `gyrosid calibrate`'s). The white noise is allan.json's white_dph_at_1hz. This is
the truth the criterion of fit flies: "the gyro as measured", not a model of anything the recording did not
show (no scale-factor error: a static recording does not determine it).
"""
import argparse
import csv
import json
import os


def burst_means(path):
    """[(mean temp_c, mean rate error in deg/h)] per burst of a recording."""
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    col = {name: i for i, name in enumerate(rows[0])}
    bursts, last_t = [], None
    for r in rows[1:]:
        t = float(r[col["t_s"]])
        if last_t is None or t - last_t > 1.0:
            bursts.append([])
        bursts[-1].append((float(r[col["temp_c"]]), (float(r[col["gyro_dps"]]) - float(r[col["ref_rate_dps"]])) * 3600))
        last_t = t
    return [(sum(s[0] for s in b) / len(b), sum(s[1] for s in b) / len(b)) for b in bursts]


def straight_line(points, reference_c):
    """Least-squares b0, b1 of y = b0 + b1 (x - reference_c)."""
    n = len(points)
    xs = [x - reference_c for x, _ in points]
    ys = [y for _, y in points]
    mx, my = sum(xs) / n, sum(ys) / n
    b1 = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return my - b1 * mx, b1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording")
    ap.add_argument("allan_json")
    ap.add_argument("out")
    ap.add_argument("--reference-c", type=float, default=20.0)
    args = ap.parse_args()
    means = burst_means(args.recording)
    b0, b1 = straight_line(means, args.reference_c)
    with open(args.allan_json) as f:
        white = json.load(f)["coefficients"]["white_dph_at_1hz"]
    text = ("# Written by docs/tutorial/sensor_from_recording.py from %s (%d bursts) and %s.\n"
            "kind: gyro\nname: the gyro as measured\nbias:\n  constant_dph: %.6g\n  temperature:\n"
            "    reference_c: %g\n    coefficients_dph: [0, %.6g]\nnoise:\n  white_dph_at_1hz: %.6g\n"
            % (os.path.basename(args.recording), len(means), os.path.basename(args.allan_json), b0, args.reference_c, b1, white))
    with open(args.out + ".tmp", "w") as f:
        f.write(text)
    os.replace(args.out + ".tmp", args.out)
    print("%s: bias %.6g deg/h at %g C, %.6g deg/h per C over %d bursts (%.1f..%.1f C); white noise %.4g deg/h at 1 Hz"
          % (args.out, b0, args.reference_c, b1, len(means), min(m[0] for m in means), max(m[0] for m in means), white))


if __name__ == "__main__":
    main()
