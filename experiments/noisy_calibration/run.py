#!/usr/bin/env python3
"""Noisy calibration at the statistical floor (issue 11): every gyrosid method, two sensors, white and
Gauss-Markov noise, 5 seeds; surface error, held-out compensation error, criterion of fit, time and memory,
predictive-band coverage; the Cramer-Rao floor and scikit-learn peers on the same recordings.

    experiments/noisy_calibration/run.py [--gyrosid build/gyrosid] [--out experiments/noisy_calibration/results]
                                         [--budget-min 25] [--part reference|sensor_c|scaling|all] [--summary-only]

Everything is cached under --out: a run stops starting new work after --budget-min minutes (exit status 3:
more to do) and the next run resumes, so the sweep goes in chunks under the experiment lock:

    until flock /tmp/gyrosid-exp.lock nice -n 10 /usr/bin/python3 experiments/noisy_calibration/run.py; \\
      do [ $? -eq 3 ] || break; sleep 60; done

Writes rows.csv (one row per recording and method) and summary.md (medians over seeds, ratios to the floor,
the issue's targets).
"""
import argparse
import csv
import hashlib
import json
import os
import subprocess
import sys
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
sys.path.insert(0, HERE)
import generator_c  # noqa: E402
from gyrosid_experiments import Runner, add_gyrosid_argument, load_json, model_size, read_recording, write_csv, write_recording  # noqa: E402

COLUMNS = ["sensor", "trajectory", "noise", "seed", "method", "samples", "nodes", "time_s", "peak_rss_mb", "termination",
           "surface_rms_dph", "surface_coverage_95", "heldout_rms_dph", "heldout_coverage_95",
           "cof_short_m", "cof_medium_m", "cof_long_1h_m", "noise_choice", "run"]


class OutOfTime(Exception):
    pass


class Experiment:
    def __init__(self, args, cfg):
        self.cfg = cfg
        self.run = Runner(args.gyrosid, args.out)
        self.out = os.path.abspath(args.out)
        self.deadline = time.time() + 60.0 * args.budget_min
        self.rows = []
        self.only = set(args.methods.split(",")) if args.methods else None

    def wanted(self, method):
        """--methods: rerun only these (the rest is taken from --keep-rows)."""
        return self.only is None or method in self.only

    def check_time(self):
        if time.time() > self.deadline:
            raise OutOfTime()

    def gyrosid(self, args, product):
        if not os.path.exists(product):
            self.check_time()
        self.run.run(args, product)

    def python(self, script, args, product):
        if os.path.exists(product):
            return
        self.check_time()
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"), OPENBLAS_NUM_THREADS=os.environ.get("OPENBLAS_NUM_THREADS", "1"))
        subprocess.run([sys.executable, os.path.join(HERE, script)] + [str(a) for a in args], check=True, env=env,
                       stderr=subprocess.DEVNULL if script == "peers.py" else None)

    # --- the pieces every method goes through -------------------------------------------------------

    def compensation_scores(self, model, recording, product):
        """rms of compensated - reference (deg/h) and the 95 % band's coverage when the model has a sigma."""
        self.gyrosid(["compensate", "--model", model, "--recording", recording, "--out", product], product)
        _, c = read_recording(product)
        d = (c["compensated_dps"] - c["ref_rate_dps"]) * 3600.0
        cov = float(np.mean(np.abs(d) <= 1.96 * c["compensated_sigma_dps"] * 3600.0)) if "compensated_sigma_dps" in c else ""
        return float(np.sqrt(np.mean(d * d))), cov, c

    def model_row(self, key, model):
        m = load_json(model)
        s = m.get("summary", {})
        row = dict(key)
        row.update({"nodes": model_size(s), "time_s": s.get("time_s", ""), "peak_rss_mb": s.get("peak_rss_mb", ""),
                    "termination": s.get("termination", ""), "samples": m.get("training", {}).get("samples", ""),
                    "noise_choice": s.get("details", {}).get("noise_choice", "")[:60]})
        return row

    def reference_scores(self, row, model, tag):
        ref = self.cfg["reference"]
        sdir = self.run.path("surfaces", tag, "x")[:-2]
        self.gyrosid(["surface", "--model", model, "--sensor", ref["sensor"], "--temp-range", ref["surface"]["temp_range"],
                      "--rate-range", ref["surface"]["rate_range"], "--out", sdir], os.path.join(sdir, "surface.json"))
        s = load_json(os.path.join(sdir, "surface.json"))
        row["surface_rms_dph"] = s["difference"]["rms_dph"]
        row["surface_coverage_95"] = s.get("sigma", {}).get("coverage_95", "")
        row["heldout_rms_dph"], row["heldout_coverage_95"], _ = self.compensation_scores(
            model, self.validation(), self.run.path("heldout", tag + ".csv"))
        cof = self.cfg["cof"]
        wanted = row["noise"] in cof["noises"] and row["method"] in cof["methods"]
        for flight in ref["flights"]:
            cdir = self.run.path("cof", tag, flight, "x")[:-2]
            if not wanted and not os.path.exists(os.path.join(cdir, "cof.json")):
                continue
            self.gyrosid(["cof", "--model", model, "--sensor", ref["sensor"], "--trajectory", flight, "--out", cdir],
                         os.path.join(cdir, "cof.json"))
            c = load_json(os.path.join(cdir, "cof.json"))
            row["cof_%s" % ("long_1h_m" if flight == "long" else flight + "_m")] = c["error_after_1h_m" if flight == "long" else "end_error_m"]
        return row

    # --- the reference sensor ---------------------------------------------------------------------------

    def validation(self):
        path = self.run.path("data", "ref", "validation.csv")
        self.gyrosid(["simulate", "--sensor", self.cfg["reference"]["sensor"], "--trajectory", self.cfg["reference"]["validation"],
                      "--noise-free", "--seed", 999, "--out", path], path)
        return path

    def sensor_with(self, noise):
        """The reference sensor's config with its noise block replaced."""
        path = self.run.path("data", "ref", "sensors", noise["name"] + ".yaml")
        if not os.path.exists(path):
            base = yaml.safe_load(builtin_text(self.cfg["reference"]["sensor"]))
            block = {"white_dph_at_1hz": noise["white_dph"]}
            if noise.get("gm_sigma_dph"):
                block["gauss_markov"] = [{"sigma_dph": noise["gm_sigma_dph"], "tau_s": noise["gm_tau_s"]}]
            base["noise"] = block
            with open(path + ".tmp", "w") as f:
                yaml.safe_dump(base, f, sort_keys=False)
            os.replace(path + ".tmp", path)
        return path

    def reference_recording(self, trajectory, noise, seed):
        path = self.run.path("data", "ref", trajectory, noise["name"], "seed%d.csv" % seed)
        self.gyrosid(["simulate", "--sensor", self.sensor_with(noise), "--trajectory", self.cfg["reference"]["trajectories"][trajectory],
                      "--seed", seed, "--out", path], path)
        return path

    def floor_args(self, noise):
        t = self.cfg["reference"]["truth_terms"]
        args = ["--model", "hybrid", "--set", "nodes=0", "--set", "bias_order=%d" % t["bias_order"],
                "--set", "surface_temperatures_c=" + t["surface_temperatures_c"], "--set", "surface_rates_dps=" + t["surface_rates_dps"],
                "--set", "noise=given", "--set", "given_white_dph_at_1hz=%g" % noise["white_dph"]]
        if noise.get("gm_sigma_dph"):
            args += ["--set", "given_gm_sigma_dph=%g" % noise["gm_sigma_dph"], "--set", "given_gm_tau_s=%g" % noise["gm_tau_s"]]
        return args

    def reference_method(self, trajectory, noise, seed, name, args, recording):
        key = {"sensor": "reference", "trajectory": trajectory, "noise": noise["name"], "seed": seed, "method": name}
        tag = "ref/%s/%s/seed%d/%s" % (trajectory, noise["name"], seed, name)
        model = self.run.path("models", tag + ".json")
        self.gyrosid(["calibrate", "--recording", recording] + args + ["--out", model], model)
        row = self.reference_scores(self.model_row(key, model), model, tag)
        self.rows.append(row)
        return row, tag

    def reference_floor(self, trajectory, noise, seed, recording):
        row, tag = self.reference_method(trajectory, noise, seed, "crb_oracle", self.floor_args(noise), recording)
        # The floor itself: the expected rms of the efficient estimate = rms of its sigma (surface grid and
        # validation samples); the CoF of the oracle's fit is one draw at the bound.
        s = load_json(os.path.join(self.run.path("surfaces", tag, "x")[:-2], "surface.json"))
        _, _, c = self.compensation_scores(self.run.path("models", tag + ".json"), self.validation(), self.run.path("heldout", tag + ".csv"))
        floor = dict(row, method="crb_floor", surface_rms_dph=s["sigma"]["rms_sigma_dph"], surface_coverage_95="",
                     heldout_rms_dph=float(np.sqrt(np.mean((c["compensated_sigma_dps"] * 3600.0) ** 2))), heldout_coverage_95="")
        self.rows.append(floor)

    def reference_peers(self, trajectory, noise, seed, recording):
        grid = self.reference_grid(self.run.path("models", "ref/%s/%s/seed%d/ols.json" % (trajectory, noise["name"], seed)))
        out = self.run.path("peers", "ref", trajectory, noise["name"], "seed%d.json" % seed)
        p = self.cfg["peers"]
        self.python("peers.py", ["--train", recording, "--eval", grid, "--eval", self.validation(), "--out", out,
                                 "--gp-subset", p["gp_subset"], "--krr-subset", p["krr_subset"], "--seed", seed], out)
        self.peer_rows(out, {"sensor": "reference", "trajectory": trajectory, "noise": noise["name"], "seed": seed},
                       os.path.basename(grid), os.path.basename(self.validation()))

    def peer_rows(self, out, key, grid_name, heldout_name):
        for name, info in load_json(out).items():
            row = dict(key, method=name + "_sklearn", time_s=info["time_s"], samples=info["samples_used"])
            row["surface_rms_dph"] = info["scores"][grid_name]["rms_dph"]
            row["surface_coverage_95"] = info["scores"][grid_name].get("coverage_95", "")
            row["heldout_rms_dph"] = info["scores"][heldout_name]["rms_dph"]
            row["heldout_coverage_95"] = info["scores"][heldout_name].get("coverage_95", "")
            self.rows.append(row)

    def reference_grid(self, model):
        """The surface comparison's grid as a recording (measured rate, temperature, true rate) for the peers."""
        path = self.run.path("data", "ref", "grid.csv")
        if not os.path.exists(path):
            ref = self.cfg["reference"]
            sdir = self.run.path("data", "ref", "grid_truth", "x")[:-2]
            self.gyrosid(["surface", "--model", model, "--sensor", ref["sensor"],
                          "--temp-range", ref["surface"]["temp_range"], "--rate-range", ref["surface"]["rate_range"], "--out", sdir],
                         os.path.join(sdir, "surface.json"))
            with open(os.path.join(sdir, "surface.csv")) as f:
                g = list(csv.DictReader(f))
            write_recording(path, ["# format: gyrosid-recording/1\n"], {
                "t_s": np.arange(len(g), dtype=float), "ref_rate_dps": np.array([float(r["rate_dps"]) for r in g]),
                "temp_c": np.array([float(r["temp_c"]) for r in g]), "gyro_dps": np.array([float(r["measured_rate_dps"]) for r in g])})
        return path

    def classical_soak(self, noise, seed):
        path = self.run.path("data", "ref", "soak", noise["name"], "seed%d.csv" % seed)
        self.gyrosid(["simulate", "--sensor", self.sensor_with(noise), "--trajectory", self.cfg["reference"]["soak"], "--seed", seed,
                      "--out", path], path)
        self.reference_method("soak", noise, seed, "classical_soak", ["--config", "builtin:calibration/classical.yaml"], path)

    def reference(self, only=None):
        cfg = self.cfg
        for noise in [n for n in cfg["noises"] if only is None or n["name"] in only]:
            for seed in noise.get("seeds", cfg["seeds"]):
                for trajectory in cfg["reference"]["trajectories"]:
                    recording = self.reference_recording(trajectory, noise, seed)
                    for m in cfg["methods"]:
                        if (m.get("slow") and seed not in cfg["slow_seeds"]) or not self.wanted(m["name"]):
                            continue
                        self.reference_method(trajectory, noise, seed, m["name"], m["args"], recording)
                    if self.wanted("crb_oracle"):
                        self.reference_floor(trajectory, noise, seed, recording)
                    if (noise["name"] in cfg["full"] or seed in cfg["slow_seeds"]) and self.wanted("gp_sklearn"):
                        self.reference_peers(trajectory, noise, seed, recording)
                if self.wanted("classical_soak"):
                    self.classical_soak(noise, seed)

    # --- time and memory against N ---------------------------------------------------------------------

    def scaling(self):
        """Training time and peak memory of the named methods on noisy recordings resampled to N samples."""
        sc = self.cfg["scaling"]
        noise = next(n for n in self.cfg["noises"] if n["name"] == sc["noise"])
        methods = {m["name"]: m["args"] for m in self.cfg["methods"]}
        for n in sc["samples"]:
            rec = self.run.path("data", "scaling", "n%d.csv" % n)
            self.gyrosid(["simulate", "--sensor", self.sensor_with(noise), "--trajectory", sc["trajectory"], "--samples", n,
                          "--seed", 1, "--out", rec], rec)
            for name in [m for m in sc["methods"] if self.wanted(m)]:
                model = self.run.path("models", "scaling", "n%d" % n, name + ".json")
                self.gyrosid(["calibrate", "--recording", rec] + methods[name] + ["--out", model], model)
                self.rows.append(self.model_row({"sensor": "reference", "trajectory": "scaling", "noise": sc["noise"], "seed": 1,
                                                 "method": name}, model))

    # --- sensor C (independent generator) ------------------------------------------------------------------

    def c_fixed_recordings(self):
        c = self.cfg["sensor_c"]
        heldout = self.run.path("data", "c", "heldout.csv")
        if not os.path.exists(heldout):
            generator_c.generate(heldout, c["heldout"], 0.0, seed=999, noise_free=True)
        grid = self.run.path("data", "c", "grid.csv")
        if not os.path.exists(grid):
            generator_c.write_grid(grid, c["grid"]["temp_c"], c["grid"]["rate_dps"])
        return grid, heldout

    def sensor_c(self, only=None):
        c = self.cfg["sensor_c"]
        methods = {m["name"]: m["args"] for m in self.cfg["methods"]}
        grid, heldout = self.c_fixed_recordings()
        for noise in [n for n in c["noises"] if only is None or n["name"] in only]:
            for seed in noise.get("seeds", self.cfg["seeds"]):
                for prog in c["programmes"]:
                    rec = self.run.path("data", "c", prog, noise["name"], "seed%d.csv" % seed)
                    if not os.path.exists(rec):
                        generator_c.generate(rec, prog, noise["white_dph"], noise.get("gm_sigma_dph", 0.0), noise.get("gm_tau_s", 0.0), seed)
                    key = {"sensor": "C", "trajectory": prog, "noise": noise["name"], "seed": seed}
                    for name in [m for m in c["methods"] if self.wanted(m)]:
                        tag = "c/%s/%s/seed%d/%s" % (prog, noise["name"], seed, name)
                        model = self.run.path("models", tag + ".json")
                        self.gyrosid(["calibrate", "--recording", rec] + methods[name] + ["--out", model], model)
                        row = self.model_row(dict(key, method=name), model)
                        row["surface_rms_dph"], row["surface_coverage_95"], _ = self.compensation_scores(model, grid, self.run.path("grid", tag + ".csv"))
                        row["heldout_rms_dph"], row["heldout_coverage_95"], _ = self.compensation_scores(model, heldout, self.run.path("heldout", tag + ".csv"))
                        self.rows.append(row)
                    self.rows.append(self.c_floor(key, rec, grid, heldout, noise))
                    if (noise["name"] in self.cfg["full"] or seed in self.cfg["slow_seeds"]) and self.wanted("gp_sklearn"):
                        out = self.run.path("peers", "c", prog, noise["name"], "seed%d.json" % seed)
                        p = self.cfg["peers"]
                        self.python("peers.py", ["--train", rec, "--eval", grid, "--eval", heldout, "--out", out, "--gp-subset", p["gp_subset"],
                                                 "--krr-subset", p["krr_subset"], "--seed", seed], out)
                        self.peer_rows(out, key, os.path.basename(grid), os.path.basename(heldout))

    def c_floor(self, key, rec, grid, heldout, noise):
        _, r = read_recording(rec)
        cov = generator_c.crb(r["t_s"], r["ref_rate_dps"], r["temp_c"], noise["white_dph"], noise.get("gm_sigma_dph", 0.0),
                              noise.get("gm_tau_s", 0.0))
        row = dict(key, method="crb_floor", samples=len(r["t_s"]), nodes=len(generator_c.THETA))
        for name, path in (("surface", grid), ("heldout", heldout)):
            _, g = read_recording(path)
            row[name + "_rms_dph"] = float(np.sqrt(np.mean(generator_c.floor_sigma(cov, g["ref_rate_dps"], g["temp_c"]) ** 2)))
        return row


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def check_cache(out, gyrosid, allow_mixed):
    """Everything under --out is reused as it is, whatever made it. So that a cache made by another build of
    gyrosid or another peers.py is never quoted as this one's, the first run writes the hashes of both into
    <out>/provenance.json and a later run with different ones stops (unless --allow-mixed-cache)."""
    now = {"gyrosid_sha256": sha256(gyrosid), "peers_py_sha256": sha256(os.path.join(HERE, "peers.py"))}
    path = os.path.join(out, "provenance.json")
    if os.path.exists(path):
        with open(path) as f:
            then = json.load(f)
        differ = [k for k in now if then.get(k) != now[k]]
        if differ and not allow_mixed:
            raise SystemExit("%s: the cache under %s was made with another %s; use a fresh --out (or --allow-mixed-cache)" % (
                path, out, " and ".join(k[:-7] for k in differ)))
        return
    cached = [d for d in ("models", "peers", "heldout", "grid") if os.path.isdir(os.path.join(out, d))]
    if cached and not allow_mixed:
        raise SystemExit("%s holds a cache (%s) of unknown provenance; use a fresh --out (or --allow-mixed-cache)" % (
            out, ", ".join(cached)))
    os.makedirs(out, exist_ok=True)
    with open(path + ".tmp", "w") as f:
        json.dump(now, f, indent=1)
    os.replace(path + ".tmp", path)


def _number(text):
    """A value read back from rows.csv: a number where it parses as one (None for an empty cell)."""
    if text == "":
        return ""
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text


def builtin_text(name):
    """A built-in config's text: configs/<relative path> of this repository."""
    assert name.startswith("builtin:")
    with open(os.path.join(HERE, "..", "..", "configs", name[len("builtin:"):])) as f:
        return f.read()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(ap)
    ap.add_argument("--config", default=os.path.join(HERE, "config.yaml"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--budget-min", type=float, default=25.0)
    ap.add_argument("--part", choices=["reference", "sensor_c", "scaling", "all"], default="all")
    ap.add_argument("--summary-only", action="store_true", help="summarise what is cached, compute nothing")
    ap.add_argument("--methods", help="comma-separated: rerun only these methods (with --keep-rows for the others)")
    ap.add_argument("--keep-rows", help="rows.csv of an earlier run: every row (recording and method) this run did not produce is kept")
    ap.add_argument("--label", default=time.strftime("%Y-%m-%d", time.gmtime()),
                    help="the `run` column of the rows this run produces (kept rows keep theirs, 'earlier' if none)")
    ap.add_argument("--allow-mixed-cache", action="store_true", help="reuse a cache made by another gyrosid or peers.py")
    args = ap.parse_args()
    cfg = yaml.safe_load(open(args.config))
    check_cache(os.path.abspath(args.out), os.path.abspath(args.gyrosid), args.allow_mixed_cache)
    e = Experiment(args, cfg)
    if args.summary_only:
        e.deadline = 0.0
    # The target noises of both sensors first, so that a run cut short by its budget has them.
    first = cfg["priority_noises"]
    stages = {"all": [("sensor_c", first), ("reference", first), ("scaling", None), ("sensor_c", None), ("reference", None)],
              "reference": [("reference", None)], "sensor_c": [("sensor_c", None)], "scaling": [("scaling", None)]}[args.part]
    done = True
    for part, only in stages:
        try:
            getattr(e, part)(only) if only else getattr(e, part)()
        except OutOfTime:
            done = False
            if not args.summary_only:  # out of budget; a summary goes on to what later stages have cached
                break
    e.rows = list({tuple(sorted((k, str(v)) for k, v in r.items())): r for r in e.rows}.values())  # stages revisit cached rows
    for r in e.rows:
        r["run"] = args.label
    if args.keep_rows:
        key = lambda r: tuple(str(r[k]) for k in ("sensor", "trajectory", "noise", "seed", "method"))
        produced = {key(r) for r in e.rows}
        with open(args.keep_rows) as f:
            # every earlier row this run did not reproduce: also rows of --methods on recordings, parts or
            # seeds the run did not reach (a --part, a budget cut) - they are dropped only when replaced
            kept = [r for r in csv.DictReader(f) if key(r) not in produced]
        e.rows += [dict({k: _number(v) for k, v in r.items()}, run=r.get("run") or "earlier") for r in kept]
    write_csv(os.path.join(e.out, "rows.csv"), e.rows, COLUMNS)
    import summarise  # noqa: E402
    summarise.write_summary(e.out, e.rows, cfg, " ".join(sys.argv), done)
    sys.stderr.write("%s: %d rows%s\n" % (e.out, len(e.rows), "" if done else " (budget reached: run again to continue)"))
    sys.exit(0 if done else 3)


if __name__ == "__main__":
    main()
