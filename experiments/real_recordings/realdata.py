"""Where the public real recordings are, and a timed run of gyrosid (wall seconds, peak resident memory)."""
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def realdata():
    """shared/realdata under the first ancestor of this checkout that holds it (/work/main or a worktree)."""
    d = HERE
    while True:
        candidate = os.path.join(d, "shared", "realdata")
        if os.path.isdir(candidate):
            return candidate
        if os.path.dirname(d) == d:
            raise SystemExit("no shared/realdata above %s: pass the data set's location" % HERE)
        d = os.path.dirname(d)


def run_timed(args):
    """Runs args under /usr/bin/time; returns (seconds, peak KB). Fails with the command's own output."""
    timing = "/tmp/gyrosid_time_%d.txt" % os.getpid()
    env = dict(os.environ, GYROSID_QUIET="1")
    r = subprocess.run(["/usr/bin/time", "-f", "%e %M", "-o", timing] + [str(a) for a in args], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.stderr.write(r.stdout + r.stderr)
        raise SystemExit("failed: %s" % " ".join(str(a) for a in args))
    with open(timing) as f:
        seconds, kb = f.read().split()
    os.remove(timing)
    return float(seconds), float(kb)
