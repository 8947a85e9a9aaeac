#!/usr/bin/python3
"""Put a recording's samples on a uniform time grid, keeping every value as recorded.

    docs/tutorial/regrid.py IN.csv OUT.csv

For a log whose clock stamps the samples with jitter while the sensor samples at a steady rate (the CubeSat
log of the tutorial stamps its samples to the millisecond: steps of 19, 20 and 21 ms). The grid runs from the
first stamp to the last in equal steps, t_s = t_first + k (t_last - t_first) / (n - 1). `gyrosid allan` needs
uniform sampling and never resamples silently; this script says in the recording's metadata that the times
were replaced. It refuses when a stamp strays more than half a step from the grid: a dropped or a doubled
sample, which no re-stamping can mend.
"""
import os
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    with open(src) as f:
        lines = f.read().splitlines()
    meta = [line for line in lines if line.startswith("#")]
    body = [line for line in lines if line and not line.startswith("#")]
    header, rows = body[0].split(","), [line.split(",") for line in body[1:]]
    col = header.index("t_s")
    t = [float(row[col]) for row in rows]
    step = (t[-1] - t[0]) / (len(t) - 1)
    for k, row in enumerate(rows):
        grid = t[0] + k * step
        if abs(t[k] - grid) > 0.5 * step:
            sys.exit("%s: sample %d: t_s %s is %.4f s from the grid of %.6f s steps (a dropped or doubled sample)"
                     % (src, k + 1, row[col], t[k] - grid, step))
        row[col] = "%.6f" % grid
    meta.append("# regrid: t_s replaced by a uniform grid of %.6f s steps (%.3f Hz) from the first to the last stamp"
                " (docs/tutorial/regrid.py); the values are as recorded" % (step, 1 / step))
    with open(out + ".tmp", "w") as f:
        f.write("\n".join(meta + [",".join(header)] + [",".join(r) for r in rows]) + "\n")
    os.replace(out + ".tmp", out)
    print("%s: %d samples on a uniform grid, %.3f Hz" % (out, len(rows), 1 / step))


if __name__ == "__main__":
    main()
