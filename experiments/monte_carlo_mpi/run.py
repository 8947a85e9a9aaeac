#!/usr/bin/env python3
"""Monte Carlo of the criterion of fit on MPI: speed-up of `mpirun -np P gyrosid-mpi` over one process, the cost
of 1,000 to 100,000 runs, and the check that every layout writes the same cof.json byte for byte.

    experiments/monte_carlo_mpi/run.py [--gyrosid build/gyrosid] [--mpirun mpirun] [--repeat 3]
                                       [--runs 1000,10000,100000] [--flights short,medium] [--out DIR]

Layouts timed on the same command (`cof --model none --monte-carlo N --seed 7`), each with one thread per
process so the cores are used by processes only:
  1 process  : gyrosid --threads 1
  2 threads  : gyrosid --threads 2           (the shared-memory path, for reference)
  MPI np=2   : mpirun -np 2 gyrosid-mpi --threads 1
The speed-up is the median wall time of `1 process` over that of `MPI np=2`. Peak memory is the largest resident
set of any process of the layout (wait4's ru_maxrss, which covers mpirun's children). Run it with the machine
otherwise idle (COORDINATION: under both locks); each timing up to 1,000 runs is the median of --repeat runs, larger ones are timed once.
"""
import argparse
import filecmp
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "lib"))
from gyrosid_experiments import add_gyrosid_argument, markdown_table, write_csv, write_text  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_rmaps_base_oversubscribe": "1"}


def timed(cmd):
    """Wall seconds and peak resident MB of `cmd` (and its waited-for children)."""
    env = dict(os.environ, GYROSID_QUIET="1", **MPI_ENV)
    start = time.perf_counter()
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
        seconds = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            err.seek(0)
            raise RuntimeError("%s failed (%d):\n%s" % (" ".join(cmd), proc.returncode, err.read().decode()))
    return seconds, usage.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--mpirun", default=shutil.which("mpirun") or "mpirun")
    ap.add_argument("--runs", default="1000,10000,100000", help="Monte Carlo sizes (comma-separated)")
    ap.add_argument("--flights", default="short,medium", help="flights; sizes above 1,000 only on the first")
    ap.add_argument("--repeat", type=int, default=3, help="timings per layout (median quoted)")
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    args = ap.parse_args()
    gyrosid = os.path.abspath(args.gyrosid)
    gyrosid_mpi = os.path.join(os.path.dirname(gyrosid), "gyrosid-mpi")
    if not os.path.exists(gyrosid_mpi):
        sys.exit("%s not found: build with libopenmpi-dev installed (scripts/setup.sh installs it)" % gyrosid_mpi)
    work = os.path.join(args.out, "work")
    os.makedirs(work, exist_ok=True)
    layouts = [("1 process", [gyrosid, "--threads", "1"]),
               ("2 threads", [gyrosid, "--threads", "2"]),
               ("MPI np=2", [args.mpirun, "-np", "2", gyrosid_mpi, "--threads", "1"])]
    rows = []
    flights = args.flights.split(",")
    for flight in flights:
        for n in [int(x) for x in args.runs.split(",")]:
            if n > 1000 and flight != flights[0]:
                continue
            repeat = args.repeat if n <= 1000 else 1
            outputs, seconds = {}, {}
            for name, prefix in layouts:
                out = os.path.join(work, "%s_%d_%s" % (flight, n, name.replace(" ", "_").replace("=", "")))
                times, peak = [], 0.0
                for _ in range(repeat):
                    shutil.rmtree(out, ignore_errors=True)
                    cmd = prefix + ["--quiet", "cof", "--model", "none", "--trajectory", flight, "--monte-carlo", str(n),
                                    "--seed", "7", "--out", out]
                    s, mb = timed(cmd)
                    times.append(s)
                    peak = max(peak, mb)
                outputs[name] = os.path.join(out, "cof.json")
                seconds[name] = statistics.median(times)
                sys.stderr.write("  %-6s N=%6d  %-9s %8.2f s (median of %d)  peak %6.1f MB\n" % (flight, n, name, seconds[name], repeat, peak))
                rows.append({"flight": flight, "runs": n, "layout": name, "repeats": repeat, "median_s": round(seconds[name], 3),
                             "ms_per_run": round(1000 * seconds[name] / n, 4), "peak_rss_mb": round(peak, 1)})
            same = all(filecmp.cmp(outputs["1 process"], outputs[k], shallow=False) for k in outputs)
            speedup = seconds["1 process"] / seconds["MPI np=2"]
            for r in rows[-len(layouts):]:
                r["speedup_vs_1"] = round(seconds["1 process"] / r["median_s"], 3)
                r["cof_json_identical"] = "yes" if same else "NO"
            sys.stderr.write("  %-6s N=%6d  MPI speed-up %.2fx, cof.json identical: %s\n" % (flight, n, speedup, same))
    cols = ["flight", "runs", "layout", "repeats", "median_s", "ms_per_run", "peak_rss_mb", "speedup_vs_1", "cof_json_identical"]
    write_csv(os.path.join(args.out, "mpi.csv"), rows, cols)
    write_text(os.path.join(args.out, "mpi.md"), "# Monte Carlo on MPI\n\nGenerated by `%s` (cpu: %d cores).\n\n" %
               (" ".join(["experiments/monte_carlo_mpi/run.py"] + sys.argv[1:]), os.cpu_count()) + markdown_table(rows, cols))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
