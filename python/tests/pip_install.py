#!/usr/bin/python3
"""The package as a user gets it: `pip install .` into a folder, then used from that folder alone.

    pip_install.py install --source REPO --build BUILD --target DIR   # pip install, then import and check
    pip_install.py example --source REPO --target DIR                 # experiments/python_example/run.py from DIR

`install` runs `python3 -m pip install --no-build-isolation --no-deps --target DIR REPO` with
GYROSID_CMAKE_BUILD_DIR=BUILD (setup.py takes this build's module instead of configuring a second build), then,
with PYTHONPATH=DIR only: the package comes from DIR with its stubs and py.typed, and the classical model
recovers a planted bias of 36 deg/h to 1e-9 deg/s. `example` runs the Python example from the installed package
and checks its numbers: the Allan deviation finds the sensor's 10 deg/h at 1 Hz, and the RBF model beats the
classical one held out and on the short flight.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

CHECK = r"""
import os, sys
import numpy as np
import gyrosid
here = os.path.dirname(gyrosid.__file__)
assert here.startswith(os.path.realpath(sys.argv[1])), "gyrosid imported from %s, not the install" % here
for name in ("_gyrosid.pyi", "py.typed"):
    assert os.path.isfile(os.path.join(here, name)), "not installed: " + name
assert gyrosid.calibrate.__doc__ and gyrosid.Recording.__doc__
t = np.arange(2000.0)
rate = 50 * np.sin(t / 40.0)
temp = -20 + 80 * t / t[-1]
rec = gyrosid.Recording({"t_s": t, "ref_rate_dps": rate, "temp_c": temp, "gyro_dps": rate + 0.01})
model = gyrosid.calibrate(rec, model="classical", options={"bias_order": 1, "sf_temperature_order": 1, "sf_rate_order": 1})
bias_dps = np.degrees(model.predict(np.column_stack([np.radians(rate[:5]), temp[:5]])))
assert np.all(np.abs(bias_dps - 0.01) < 1e-9), bias_dps
print("gyrosid from %s: planted bias 0.01 deg/s recovered as %.12f" % (here, bias_dps[0]))
"""


def python_env(target):
    """The environment with PYTHONPATH = the install folder only."""
    return dict(os.environ, PYTHONPATH=target, GYROSID_QUIET="1")


def install(args):
    shutil.rmtree(args.target, ignore_errors=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["GYROSID_CMAKE_BUILD_DIR"] = args.build
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-index",
                    "--target", args.target, args.source], check=True, env=env)
    subprocess.run([sys.executable, "-c", CHECK, args.target], check=True, env=python_env(args.target),
                   cwd=tempfile.gettempdir())


def example(args):
    out = tempfile.mkdtemp(prefix="gyrosid-python-example-")
    script = os.path.join(args.source, "experiments", "python_example", "run.py")
    subprocess.run([sys.executable, script, "--out", out], check=True, env=python_env(args.target),
                   cwd=out)
    with open(os.path.join(out, "results.json")) as f:
        results = json.load(f)
    arw = results["angle_random_walk_deg_rt_h"]
    failures = []
    if abs(arw / (10 / 60) - 1) > 0.05:
        failures.append("angle random walk %g deg/sqrt(h), planted 10 deg/h at 1 Hz = %g" % (arw, 10 / 60))
    if not results["rbf"]["held_out_rms_dph"] < results["classical"]["held_out_rms_dph"]:
        failures.append("rbf held out %g not below classical %g" % (results["rbf"]["held_out_rms_dph"],
                                                                    results["classical"]["held_out_rms_dph"]))
    if not results["rbf"]["short_m"] < results["classical"]["short_m"]:
        failures.append("rbf short flight %g m not below classical %g m" % (results["rbf"]["short_m"], results["classical"]["short_m"]))
    for failure in failures:
        print("FAIL: " + failure, file=sys.stderr)
    if not failures:
        shutil.rmtree(out)
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("step", choices=["install", "example"])
    ap.add_argument("--source", required=True)
    ap.add_argument("--build")
    ap.add_argument("--target", required=True)
    args = ap.parse_args()
    if args.step == "install":
        if not args.build:
            ap.error("install needs --build")
        install(args)
        return 0
    return example(args)


if __name__ == "__main__":
    sys.exit(main())
