"""Shared helpers for experiment drivers: run the gyrosid command, cache results, write tables and plots.

Experiments call the gyrosid executable (each calibration in its own process, so its peak memory is its
own) and keep every intermediate file under the experiment's output folder; a rerun reuses what exists
unless --force is given.
"""
import csv
import io
import json
import os
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_GYROSID = os.path.join(ROOT, "build", "gyrosid")
DPH_PER_DPS = 3600.0  # deg/h per deg/s


def add_gyrosid_argument(parser):
    """The --gyrosid option every driver takes, with one default: the repository's build/gyrosid."""
    parser.add_argument("--gyrosid", default=DEFAULT_GYROSID, help="gyrosid executable (default: %(default)s)")


def read_recording(path):
    """A recording (RECORDING_FORMAT.md) as (metadata lines, {column name: numpy array}); '#' lines are kept
    verbatim as metadata, columns are found by name."""
    import numpy as np
    meta, lines = [], []
    with open(path) as f:
        for line in f:
            if not line.strip():
                continue
            (meta if line.startswith("#") else lines).append(line)
    header = [c.strip() for c in lines[0].strip().split(",")]
    data = np.loadtxt(io.StringIO("".join(lines[1:])), delimiter=",", ndmin=2)
    return meta, {name: data[:, i].copy() for i, name in enumerate(header)}


def write_recording(path, meta, cols):
    """Writes (metadata lines, columns) as a recording, atomically, every digit kept."""
    import numpy as np
    names = list(cols.keys())
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.writelines(meta)
        f.write(",".join(names) + "\n")
        np.savetxt(f, np.column_stack([cols[n] for n in names]), delimiter=",", fmt="%.17g")
    os.replace(tmp, path)


def rate_error_dph(cols, measured="gyro_dps", reference="ref_rate_dps"):
    """measured - reference of a recording's columns, deg/h."""
    return (cols[measured] - cols[reference]) * DPH_PER_DPS


class Runner:
    def __init__(self, gyrosid, out_dir, force=False):
        self.gyrosid = os.path.abspath(gyrosid)
        self.out = os.path.abspath(out_dir)
        self.force = force
        os.makedirs(self.out, exist_ok=True)

    def path(self, *parts):
        p = os.path.join(self.out, *parts)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        return p

    def run(self, args, product):
        """Runs `gyrosid args...` unless `product` already exists (and --force is off). Returns seconds."""
        if os.path.exists(product) and not self.force:
            return 0.0
        start = time.time()
        env = dict(os.environ, GYROSID_QUIET="1")
        result = subprocess.run([self.gyrosid] + [str(a) for a in args], capture_output=True, text=True, env=env)
        if result.returncode != 0:
            sys.stderr.write(result.stdout + result.stderr)
            raise RuntimeError("gyrosid %s failed" % " ".join(str(a) for a in args))
        return time.time() - start


def set_args(options):
    """`--set key=value` arguments for gyrosid from a dict (YAML booleans as true/false)."""
    out = []
    for k, v in options.items():
        out += ["--set", "%s=%s" % (k, str(v).lower() if isinstance(v, bool) else v)]
    return out


def load_json(path):
    with open(path) as f:
        return json.load(f)


def model_size(summary):
    """Nodes of an RBF model, or coefficients of another, from a model file's solver summary."""
    details = summary.get("details", {})
    return details.get("nodes", details.get("parameters", ""))


def write_csv(path, rows, columns):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)
    os.replace(tmp, path)


def fmt(v, digits=3):
    if isinstance(v, float):
        return "%.*g" % (digits, v)
    return str(v)


def markdown_table(rows, columns, headers=None):
    headers = headers or columns
    out = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        out.append("| " + " | ".join(fmt(r.get(c, "")) for c in columns) + " |")
    return "\n".join(out) + "\n"


def write_text(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def gnuplot(png, script):
    """Renders a gnuplot script (without terminal/output) into png."""
    tmp_png = png + ".tmp.png"
    full = "set terminal pngcairo noenhanced size 960,640 font 'Sans,10'\nset output '%s'\n%s\nset output\n" % (tmp_png, script)
    subprocess.run(["gnuplot"], input=full, text=True, check=True)
    os.replace(tmp_png, png)
