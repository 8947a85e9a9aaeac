#!/usr/bin/env python3
"""Issue 33's scale targets for the production lot: `lot learn` / `lot screen` on 1 thread, 2 threads and
2 MPI ranks (wall time, peak memory per process, the same bytes), a killed and resumed `lot learn`, and the
peak memory of `lot learn` at 1,000 to 10,000 units.

    /usr/bin/python3 experiments/production_lot/scale_mpi.py --bin /tmp/lotscale-bin \
        [--parts layouts,resume,pipeline,memory] [--units 1000] [--repeats 1] [--memory-sizes 1000,2000,10000]

Inputs (made by run.py --parts scale, family A, lot seed 200, 2 % defects): <--lot-dir>/u00000..u00999/dual.csv
(62-min dual scan) and short.csv (15-min). `lot screen` names each unit's screen.json folder by its recording's path
from the recordings' common folder; the short recordings are reached through symlinks <--work>/rec/uNNNNN.csv. For the memory part, 10,000
recordings are symlinks <--work-10k>/short/uNNNNN.csv to unit NNNNN mod 1,000's short.csv: each recording is
calibrated on its own, so memory and time are those of 10,000 units (the lot learned from 10 copies of each unit
is not a population; memory is the question).

Layouts (each process one thread, so the two cores are used by threads or by processes):
  1p1t : gyrosid --threads 1
  1p2t : gyrosid --threads 2
  mpi2 : mpirun -np 2 gyrosid-mpi --threads 1   (OMPI_* as experiments/monte_carlo_mpi)
Every timed command runs holding flock(/tmp/gyrosid-cpu.lock) (another session shares the two cores); wall is
the median over --repeats runs; peak RSS per process from /usr/bin/time -v (one file per MPI rank).

Parts:
  layouts  `lot learn --recordings <N dual> --set shupe=true` and `lot screen` of the N short recordings against
           the 1p2t lot, per layout; cmp of lot.json, screens.csv and every screen.json across layouts.
  resume   mpi2 `lot learn` on --resume-units dual scans: uninterrupted, then a run SIGKILLed (mpirun and
           every rank) at two seeded random moments and continued with --resume; cmp with the uninterrupted lot.json.
  pipeline learn (50 training units' dual scans) + `calibrate --prior` of every unit's short recording (one process
           per unit, two at a time) + batch `lot screen` of all of them: 1p2t, and mpi2 for learn and screen.
  memory   `lot learn` (1p2t) on the first N short recordings for N in --memory-sizes; peak RSS and wall.

Work (cached, skip-if-done: a finished measurement is a stamp file run.json) under --work (default
/tmp/lotscale/work). Writes results/scale_mpi.md and results/scale_mpi.json.
"""
import argparse
import fcntl
import filecmp
import json
import os
import random
import re
import signal
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
LOCK = "/tmp/gyrosid-cpu.lock"
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_rmaps_base_oversubscribe": "1"}
LAYOUTS = ("1p1t", "1p2t", "mpi2")
GREYBOX = ["--set", "shupe=true"]  # run.py's GREYBOX
TRAIN = 50  # run.py's training units


class Cpu:
    """flock(2) on the shared lock file: the same lock as flock(1) on the command line."""

    enabled = True  # --no-lock: for a part whose times are not the result (the kill/resume check)

    def __enter__(self):
        self.f = open(LOCK, "a")
        if Cpu.enabled:
            fcntl.flock(self.f, fcntl.LOCK_EX)
        return self

    def __exit__(self, *exc):
        if Cpu.enabled:
            fcntl.flock(self.f, fcntl.LOCK_UN)
        self.f.close()


def load(path, default=None):
    if not os.path.exists(path):
        return default
    with open(path) as f:
        return json.load(f)


def save(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path + ".tmp", "w") as f:
        json.dump(obj, f, indent=1)
    os.replace(path + ".tmp", path)


def command(a, layout, argv, timefile):
    """The argv of `gyrosid argv` in `layout`, each process under /usr/bin/time -v writing timefile.<rank>."""
    if layout == "mpi2":
        wrap = 'exec /usr/bin/time -v -o "$0.$OMPI_COMM_WORLD_RANK" "$@"'
        return [a.mpirun, "-np", "2", "sh", "-c", wrap, timefile, os.path.join(a.bin, "gyrosid-mpi"), "--quiet", "--threads", "1"] + argv
    threads = "1" if layout == "1p1t" else "2"
    return ["/usr/bin/time", "-v", "-o", timefile + ".0", os.path.join(a.bin, "gyrosid"), "--quiet", "--threads", threads] + argv


def peak_mb(timefile):
    """Peak RSS (MB) of each process that wrote timefile.<rank>."""
    return [int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024.0 for t in time_files(timefile)]


def cpu_s(timefile):
    """User + system CPU seconds of all the processes (robust to other load on the machine, unlike wall)."""
    return sum(float(re.search(r"User time \(seconds\): ([\d.]+)", t).group(1)) + float(re.search(r"System time \(seconds\): ([\d.]+)", t).group(1))
               for t in time_files(timefile))


def time_files(timefile):
    out, rank = [], 0
    while os.path.exists("%s.%d" % (timefile, rank)):
        out.append(open("%s.%d" % (timefile, rank)).read())
        rank += 1
    return out


def timed(a, layout, argv, timefile, lock=True):
    """Runs the command (holding the CPU lock); wall seconds and per-process peak MB."""
    cmd = command(a, layout, argv, timefile)
    env = dict(os.environ, GYROSID_QUIET="1", **MPI_ENV)
    with Cpu() if lock else open(os.devnull):
        start = time.perf_counter()
        r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        seconds = time.perf_counter() - start
        load_after = os.getloadavg()[0]
    if r.returncode != 0:
        raise RuntimeError("failed (%d): %s ...\n%s%s" % (r.returncode, " ".join(cmd[:14]), r.stdout[-3000:], r.stderr[-3000:]))
    return seconds, peak_mb(timefile), r.stdout, cpu_s(timefile), load_after


def measure(a, name, layout, argv, out_of, repeats):
    """A measurement cached in <work>/<name>/<layout>/run.json: each repeat writes into rep<k>/; the outputs of
    rep0 are the ones compared. argv's '{out}' is replaced by the repeat's folder."""
    base = os.path.join(a.work, name, layout)
    stamp = os.path.join(base, "run.json")
    runs = load(stamp, [])
    while len(runs) < repeats:
        rep = os.path.join(base, "rep%d" % len(runs))
        if os.path.exists(rep):
            subprocess.run(["rm", "-rf", rep], check=True)
        os.makedirs(rep)
        args = [x.replace("{out}", rep) for x in argv]
        seconds, mb, stdout, cpu, load1 = timed(a, layout, args, os.path.join(rep, "time"))
        runs.append({"wall_s": seconds, "cpu_s": cpu, "load1_after": load1, "peak_mb_per_process": mb, "stdout_tail": stdout[-400:]})
        save(stamp, runs)
        print("%s %s rep %d: %.1f s, %s MB" % (name, layout, len(runs) - 1, seconds, ", ".join("%.0f" % m for m in mb)), flush=True)
    return {"wall_s": float(np.median([r["wall_s"] for r in runs])), "repeats": len(runs), "walls_s": [r["wall_s"] for r in runs],
            "cpu_s": float(np.median([r["cpu_s"] for r in runs])), "load1_after": [r["load1_after"] for r in runs],
            "peak_mb_per_process": [max(r["peak_mb_per_process"][k] for r in runs) for k in range(len(runs[0]["peak_mb_per_process"]))],
            "out": out_of(os.path.join(base, "rep0"))}


def same_tree(a_dir, b_dir):
    """Every file under a_dir (but the time files) equal byte for byte to b_dir's, and the same set of files."""
    def files(d):
        out = set()
        for root, _, names in os.walk(d):
            for n in names:
                if not n.startswith("time."):
                    out.add(os.path.relpath(os.path.join(root, n), d))
        return out
    fa, fb = files(a_dir), files(b_dir)
    if fa != fb:
        return False, len(fa)
    return all(filecmp.cmp(os.path.join(a_dir, f), os.path.join(b_dir, f), shallow=False) for f in fa), len(fa)


def recordings(a, n, kind):
    """The first n units' dual scans, or their short recordings through <work>/rec/uNNNNN.csv symlinks."""
    if kind == "dual":
        return [os.path.join(a.lot_dir, "u%05d" % i, "dual.csv") for i in range(n)]
    out = []
    for i in range(n):
        link = os.path.join(a.work, "rec", "u%05d.csv" % i)
        if not os.path.lexists(link):
            os.makedirs(os.path.dirname(link), exist_ok=True)
            os.symlink(os.path.join(a.lot_dir, "u%05d" % i, "short.csv"), link)
        out.append(link)
    return out


def recordings_10k(a, n):
    """n short recordings: symlinks to unit (i mod 1,000)'s short.csv."""
    out = []
    for i in range(n):
        link = os.path.join(a.work_10k, "short", "u%05d.csv" % i)
        if not os.path.lexists(link):
            os.makedirs(os.path.dirname(link), exist_ok=True)
            os.symlink(os.path.join(a.lot_dir, "u%05d" % (i % 1000), "short.csv"), link)
        out.append(link)
    return out


def layouts_part(a):
    n = a.units
    res = {"units": n, "learn": {}, "screen": {}}
    learn = ["lot", "learn", "--recordings"] + recordings(a, n, "dual") + GREYBOX + ["--out", "{out}/lot.json"]
    for lay in LAYOUTS:
        res["learn"][lay] = measure(a, "learn_dual%d" % n, lay, learn, lambda d: d, a.repeats)
    lot = os.path.join(a.work, "learn_dual%d" % n, "1p2t", "rep0", "lot.json")
    screen = ["lot", "screen", "--prior", lot, "--recording"] + recordings(a, n, "short") + ["--out", "{out}/screens"]
    for lay in LAYOUTS:
        res["screen"][lay] = measure(a, "screen_short%d" % n, lay, screen, lambda d: d, a.repeats)
    for what in ("learn", "screen"):
        r = res[what]
        ref = r["1p1t"]["out"]
        for lay in LAYOUTS:
            r[lay]["speedup_over_1p1t"] = r["1p1t"]["wall_s"] / r[lay]["wall_s"]
            if what == "learn":
                r[lay]["identical_to_1p1t"] = filecmp.cmp(os.path.join(ref, "lot.json"), os.path.join(r[lay]["out"], "lot.json"), shallow=False)
            else:
                same, count = same_tree(os.path.join(ref, "screens"), os.path.join(r[lay]["out"], "screens"))
                r[lay]["identical_to_1p1t"], r[lay]["files_compared"] = same, count
    res["screen"]["flagged"] = sum(1 for line in open(os.path.join(res["screen"]["1p1t"]["out"], "screens", "screens.csv")).readlines()[1:]
                                   if line.split(",")[1] == "true")
    return res


def run_killable(a, argv, timefile, kill_after):
    """mpi2 `argv`; SIGKILL to mpirun and every process below it after kill_after s (None: to the end).
    Returns (seconds, killed)."""
    cmd = command(a, "mpi2", argv, timefile)
    env = dict(os.environ, GYROSID_QUIET="1", **MPI_ENV)
    start = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, start_new_session=True)
    try:
        p.wait(timeout=kill_after)
        if p.returncode != 0:
            raise RuntimeError("failed (%d): %s" % (p.returncode, " ".join(cmd[:14])))
        return time.perf_counter() - start, False
    except subprocess.TimeoutExpired:
        tree = descendants(p.pid)  # mpirun puts each rank in a process group of its own: kill the whole tree
        for pid in [p.pid] + tree:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        p.wait()
        while any(alive(pid) for pid in tree):
            time.sleep(0.2)
        return time.perf_counter() - start, True


def descendants(pid):
    """Every process below pid (/proc/<pid>/task/*/children)."""
    out = []
    for task in os.listdir("/proc/%d/task" % pid) if os.path.exists("/proc/%d/task" % pid) else []:
        try:
            children = open("/proc/%d/task/%s/children" % (pid, task)).read().split()
        except OSError:
            continue
        for c in map(int, children):
            out += [c] + descendants(c)
    return out


def alive(pid):
    """pid exists and is not a zombie."""
    try:
        return open("/proc/%d/stat" % pid).read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def resume_part(a):
    base = os.path.join(a.work, "resume%d" % a.resume_units)
    stamp = os.path.join(base, "run.json")
    if load(stamp):
        return load(stamp)
    argv = ["lot", "learn", "--recordings"] + recordings(a, a.resume_units, "dual") + GREYBOX
    ref = os.path.join(base, "uninterrupted")
    subprocess.run(["rm", "-rf", ref], check=True)
    os.makedirs(ref)
    with Cpu():
        full_s, _ = run_killable(a, argv + ["--out", ref + "/lot.json"], ref + "/time", None)
        rng = random.Random(33)
        out = os.path.join(base, "killed")
        subprocess.run(["rm", "-rf", out], check=True)
        os.makedirs(out)
        checkpoint = os.path.join(out, ".lot.json_checkpoint.json")
        kills = []
        saved = 0
        for k in range(2):
            at = rng.uniform(0.1, 0.8) * full_s * (1.0 - saved / a.resume_units)  # a random moment of the work left
            seconds, killed = run_killable(a, argv + ["--out", out + "/lot.json"] + (["--resume"] if k else []), out + "/time", at)
            saved = len(json.load(open(checkpoint))["series"].get("units", [])) // (2 * 77 + 2) if os.path.exists(checkpoint) else 0
            kills.append({"kill_after_s": at, "killed": killed, "units_in_checkpoint": saved})
            print("resume: run %d killed after %.1f s (%s), %d units in the checkpoint" % (k, at, killed, saved), flush=True)
        last_s, _ = run_killable(a, argv + ["--out", out + "/lot.json", "--resume"], out + "/time", None)
    res = {"units": a.resume_units, "layout": "mpi2", "uninterrupted_s": full_s, "kills": kills, "final_resume_s": last_s,
           "identical": filecmp.cmp(ref + "/lot.json", out + "/lot.json", shallow=False),
           "checkpoint_left": os.path.exists(checkpoint)}
    save(stamp, res)
    return res


def calibrate_all(a, prior, shorts, out_dir):
    """`calibrate --prior` of every short recording, one process per unit, two at a time, --threads 1."""
    procs, i = [], 0
    env = dict(os.environ, GYROSID_QUIET="1")
    os.makedirs(out_dir, exist_ok=True)
    while i < len(shorts) or procs:
        while i < len(shorts) and len(procs) < 2:
            out = os.path.join(out_dir, os.path.basename(shorts[i])[:-4] + ".json")
            procs.append(subprocess.Popen([os.path.join(a.bin, "gyrosid"), "--quiet", "--threads", "1", "calibrate", "--recording", shorts[i],
                                           "--prior", prior, "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env))
            i += 1
        p = procs.pop(0)
        _, err = p.communicate()
        if p.returncode != 0:
            raise RuntimeError("calibrate failed: %s" % err.decode()[-2000:])


def pipeline_part(a):
    res = {}
    n = a.units
    shorts = recordings(a, n, "short")
    for lay in a.pipeline_layouts.split(","):
        base = os.path.join(a.work, "pipeline%d" % n, lay)
        stamp = os.path.join(base, "run.json")
        if load(stamp):
            res[lay] = load(stamp)
            continue
        subprocess.run(["rm", "-rf", base], check=True)
        os.makedirs(base)
        stages = {}
        with Cpu():
            start = time.perf_counter()
            learn = ["lot", "learn", "--recordings"] + recordings(a, TRAIN, "dual") + GREYBOX + ["--out", base + "/lot.json"]
            stages["learn_50_s"], mb_learn, _, _, _ = timed(a, lay, learn, base + "/time_learn", lock=False)
            t = time.perf_counter()
            calibrate_all(a, base + "/lot.json", shorts, base + "/models")
            stages["calibrate_prior_s"] = time.perf_counter() - t
            screen = ["lot", "screen", "--prior", base + "/lot.json", "--recording"] + shorts + ["--out", base + "/screens"]
            stages["screen_s"], mb_screen, _, _, _ = timed(a, lay, screen, base + "/time_screen", lock=False)
            wall = time.perf_counter() - start
        res[lay] = {"units": n, "wall_s": wall, "load1_after": os.getloadavg()[0], "stages_s": stages, "peak_mb_learn": mb_learn, "peak_mb_screen": mb_screen}
        save(stamp, res[lay])
        print("pipeline %s: %.0f s %s" % (lay, wall, stages), flush=True)
    if len(res) == 2:
        p1, p2 = (os.path.join(a.work, "pipeline%d" % n, lay) for lay in ("1p2t", "mpi2"))
        res["identical"] = {"lot.json": filecmp.cmp(p1 + "/lot.json", p2 + "/lot.json", shallow=False),
                            "models": same_tree(p1 + "/models", p2 + "/models")[0], "screens": same_tree(p1 + "/screens", p2 + "/screens")[0]}
    return res


def memory_part(a):
    res = {}
    for n in (int(x) for x in a.memory_sizes.split(",") if x):
        argv = ["lot", "learn", "--recordings"] + recordings_10k(a, n) + GREYBOX + ["--out", "{out}/lot.json"]
        m = measure(a, "memory_short%d" % n, "1p2t", argv, lambda d: d, 1)
        m["lot_json_bytes"] = os.path.getsize(os.path.join(m["out"], "lot.json"))
        res[str(n)] = m
    return res


def fmt_mb(mb):
    return " / ".join("%.0f" % x for x in mb)


def write_results(a, summary):
    lines = ["# production_lot: scale on two cores (issue 33)", "",
             "`experiments/production_lot/scale_mpi.py` (binaries: %s, md5 %s). Family A, lot seed 200 (run.py's scale lot)." % (
                 a.bin, summary["binaries_md5"]), ""]
    lay = summary.get("layouts")
    if lay:
        lines += ["## 1 thread, 2 threads, 2 MPI ranks (%d units)" % lay["units"], "",
                  "| command | layout | wall, s (median of runs) | runs | speed-up over 1 thread | CPU s (all processes) | load (1 min) after | peak RSS per process, MB | output identical to 1 thread |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for what, label in (("learn", "`lot learn` (dual scans)"), ("screen", "`lot screen` (15-min recordings)")):
            for name in LAYOUTS:
                r = lay[what][name]
                same = ("yes" if r["identical_to_1p1t"] else "**no**") + (" (%d files)" % r["files_compared"] if "files_compared" in r else "")
                lines.append("| %s | %s | %.1f | %d | %.2fx | %.0f | %s | %s | %s |" % (label, name, r["wall_s"], r["repeats"], r["speedup_over_1p1t"], r["cpu_s"],
                                                                             " / ".join("%.1f" % x for x in r["load1_after"]), fmt_mb(r["peak_mb_per_process"]), same))
        lines += ["", "Screened: %d of %d units out of family at alpha 0.01 (the lot learned from all %d units' dual scans)." % (
            lay["screen"]["flagged"], lay["units"], lay["units"]), ""]
    res = summary.get("resume")
    if res:
        lines += ["## Killed and resumed (`mpirun -np 2 gyrosid-mpi lot learn`, %d units' dual scans)" % res["units"], "",
                  "Uninterrupted: %.1f s. " % res["uninterrupted_s"] + "; ".join(
                      "kill %d (SIGKILL to mpirun and every rank) after %.1f s: %s" % (
                          k + 1, x["kill_after_s"], "%d units in the checkpoint" % x["units_in_checkpoint"] if x["killed"] else "the run had finished (no kill)")
                      for k, x in enumerate(res["kills"])) + ". The last `--resume`: %.1f s. lot.json identical to the uninterrupted run's: **%s**; checkpoint removed: %s." % (
                      res["final_resume_s"], "yes" if res["identical"] else "no", "no" if res["checkpoint_left"] else "yes"), ""]
    pipe = summary.get("pipeline")
    if pipe:
        lines += ["## The 1,000-unit pipeline (simulation done before; learn + calibrate --prior + screen)", "",
                  "| layout | learn (50 dual scans), s | calibrate --prior x N (2 processes), s | lot screen x N, s | total, s | peak MB learn / screen |",
                  "|---|---|---|---|---|---|"]
        for name in ("1p2t", "mpi2"):
            if name in pipe:
                p = pipe[name]
                s = p["stages_s"]
                lines.append("| %s | %.1f | %.1f | %.1f | %.0f | %s ; %s |" % (name, s["learn_50_s"], s["calibrate_prior_s"], s["screen_s"], p["wall_s"],
                                                                           fmt_mb(p["peak_mb_learn"]), fmt_mb(p["peak_mb_screen"])))
        if "identical" in pipe:
            lines += ["", "1p2t against mpi2: " + ", ".join("%s %s" % (k, "identical" if v else "DIFFERENT") for k, v in pipe["identical"].items()) + "."]
        lines.append("")
    mem = summary.get("memory")
    if mem:
        lines += ["## Peak memory of `lot learn` against the number of units (15-min recordings, 1 process, 2 threads)", "",
                  "| units | wall, s | CPU s | peak RSS, MB | lot.json, bytes |", "|---|---|---|---|---|"]
        for n, m in sorted(mem.items(), key=lambda kv: int(kv[0])):
            lines.append("| %s | %.1f | %.0f | %s | %d |" % (n, m["wall_s"], m["cpu_s"], fmt_mb(m["peak_mb_per_process"]), m["lot_json_bytes"]))
        lines.append("")
    os.makedirs(a.results, exist_ok=True)
    with open(os.path.join(a.results, "scale_mpi.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    save(os.path.join(a.results, "scale_mpi.json"), summary)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="/tmp/lotscale-bin", help="folder holding gyrosid and gyrosid-mpi")
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--lot-dir", default="/tmp/gyrosid-production-lot/A/lot200_n1000")
    ap.add_argument("--work", default="/tmp/lotscale/work")
    ap.add_argument("--work-10k", default="/tmp/gyrosid-production-lot-10k")
    ap.add_argument("--parts", default="layouts,resume,pipeline,memory")
    ap.add_argument("--units", type=int, default=1000)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--resume-units", type=int, default=300)
    ap.add_argument("--memory-sizes", default="1000,2000,10000")
    ap.add_argument("--pipeline-layouts", default="1p2t,mpi2")
    ap.add_argument("--no-lock", action="store_true", help="run without the CPU lock (times then not comparable)")
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    a = ap.parse_args()
    a.bin, a.work = os.path.abspath(a.bin), os.path.abspath(a.work)
    Cpu.enabled = not a.no_lock
    summary = load(os.path.join(a.results, "scale_mpi.json"), {})
    md5 = subprocess.run(["md5sum", os.path.join(a.bin, "gyrosid"), os.path.join(a.bin, "gyrosid-mpi")], capture_output=True, text=True).stdout.split()
    summary["binaries_md5"] = "%s / %s" % (md5[0][:8], md5[2][:8])
    parts = {"layouts": layouts_part, "resume": resume_part, "pipeline": pipeline_part, "memory": memory_part}
    for name in a.parts.split(","):
        summary[name] = parts[name](a)
        write_results(a, summary)
    print(open(os.path.join(a.results, "scale_mpi.md")).read())


if __name__ == "__main__":
    main()
