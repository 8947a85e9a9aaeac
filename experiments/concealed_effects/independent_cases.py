"""The concealed-effects cases on the independent generator (independent.py): which recordings, how each is
built, and how explain's answer on it is scored. Every failure class of issue 12 is a case family here, at
several magnitudes and seeds: Shupe alone and a lag alone (each must be named without the other beside it),
hysteresis alone, asymmetry alone (absorbed in part by the baseline's scale-factor surface), two and three
effects at once, steps and ramps outside the library, a supply-voltage dependence, and negative controls.
explain gets no simulation and no options - as a new user would run it.
"""
import csv
import json
import os
import subprocess

import numpy as np

import independent as ind
from gyrosid_experiments import add_gyrosid_argument, write_recording

OUTSIDE = ("bias_step", "bias_ramp", "supply_voltage")
PARAMETER = {"shupe": "k_dph_per_cpm", "thermal_lag": "tau_s", "thermal_hysteresis": "offset_dph",
             "scale_factor_asymmetry": "asymmetry_ppm", "aging_trend": "k_dph_per_h"}


def jobs(cfg, out, seeds):
    """The job list: dicts with group, case, seed, dir and the generator's case spec."""
    out_jobs = []

    def add(group, case, seed, spec):
        out_jobs.append({"generator": "independent", "group": group, "case": case, "seed": seed, "spec": spec,
                         "dir": os.path.join(out, "independent", group, case, "seed%d" % seed)})

    for i, m in enumerate(cfg["magnitudes"]):
        for effect in cfg["effects"]:
            for seed in range(1, seeds + 1):
                add("effect", "%s@%s" % (effect, m), 5000 + 100 * i + seed, {"effects": [{"id": effect, "magnitude": m}]})
    for tau in cfg["lag_tau_s"]:
        for seed in range(1, seeds + 1):
            add("effect", "thermal_lag@%ss" % tau, 6000 + seed + tau, {"coil_tau_s": tau})
    for name, spec in cfg["combinations"].items():
        for m in spec["magnitudes"]:
            for seed in range(1, seeds + 1):
                effects = [{"id": e, "magnitude": m} for e in spec["effects"] if e != "thermal_lag"]
                case = {"effects": effects}
                if "thermal_lag" in spec["effects"]:
                    case["coil_tau_s"] = spec["lag_tau_s"]
                add("combination", "%s@%s" % (name, m), 7000 + seed + int(100 * m), case)
    for effect, mags in cfg["outside_library"].items():
        for m in mags:
            for seed in range(1, seeds + 1):
                add("outside", "%s@%s" % (effect, m), 8000 + seed + int(100 * m), {"effects": [{"id": effect, "magnitude": m}]})
    for name, spec in cfg["controls"].items():
        for seed in range(1, spec["seeds"] + 1):
            add("control", name, 9000 + seed, {"noise": spec.get("noise", {})})
    return out_jobs


def build(job):
    """Writes the job's recording, its truth and its noise (if absent); returns the truth."""
    d = job["dir"]
    truth_path = os.path.join(d, "truth.json")
    if os.path.exists(truth_path):
        return json.load(open(truth_path))
    os.makedirs(d, exist_ok=True)
    r = ind.make_recording(job["spec"], job["seed"])
    meta = ["# format: gyrosid-recording/1\n",
            "# sensor: interferometric FOG written by experiments/concealed_effects/independent.py (not gyrosid's simulator)\n",
            "# description: %s, seed %d, programme %s\n" % (job["case"], job["seed"], r["truth"]["programme"]),
            "# sample_rate_hz: 1\n"]
    return save_case(d, meta, r)


def save_case(d, meta, r):
    """Writes a generated case into d - recording.csv (with the metadata lines), noise.npy, planted.npy and,
    last and atomically, truth.json (its presence marks the case complete) - and returns the truth."""
    write_recording(os.path.join(d, "recording.csv"), meta, r["cols"])
    np.save(os.path.join(d, "noise.npy"), r["noise_dph"])
    np.save(os.path.join(d, "planted.npy"), r["truth"].pop("planted_unabsorbed_dph"))
    truth_path = os.path.join(d, "truth.json")
    with open(truth_path + ".tmp", "w") as f:
        json.dump(r["truth"], f)
    os.replace(truth_path + ".tmp", truth_path)
    return r["truth"]


def add_binary_arguments(parser):
    """--gyrosid, --tag and --out of a driver that runs one binary's explain on cached recordings."""
    add_gyrosid_argument(parser)
    parser.add_argument("--tag", required=True, help="name of this binary's results (a folder in every case)")
    parser.add_argument("--out", required=True, help="work folder: recordings, explain outputs and <tag>.csv")


def explained_rows(gyrosid, tag, jobs):
    """(job, truth, explain's answer, scored row) for each job: its recording built when absent, explained by
    the binary into <dir>/<tag> unless already there."""
    for job in jobs:
        truth = build(job)
        ex = explained(gyrosid, job, tag)
        yield job, truth, ex, score(job, truth, ex, job["dir"], sub=tag)


def write_rows(path, rows, keys):
    """The rows as a csv table with these columns (others left out)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def explained(gyrosid, job, tag):
    """explain's answer on the job's recording (run into <dir>/<tag> unless already there)."""
    out = os.path.join(job["dir"], tag)
    if not os.path.exists(os.path.join(out, "explain.json")):
        subprocess.run([gyrosid, "explain", "--recording", os.path.join(job["dir"], "recording.csv"), "--seed", str(job["seed"]),
                        "--out", out], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.load(open(os.path.join(out, "explain.json")))


def explain_args(job):
    return ["--seed", job["seed"]]


def named_and_alternatives(ex):
    """Every effect id explain named, and for each the ids it lists as indistinguishable or absorbed."""
    out = {}
    for e in ex["effects"]:
        out[e["id"]] = set(e["alternatives"])
    return out


def score(job, truth, ex, d, sub="explain"):
    """One row of the table: naming, false discoveries, held-out excess removed, localisation, time (explain's
    outputs in d/sub)."""
    named = named_and_alternatives(ex)
    planted = [e["id"] for e in truth["effects"]]
    absorbed = {a["id"] for a in ex.get("absorbed_alternatives", [])}
    covered = set(named) | {a for alts in named.values() for a in alts}
    row = {"generator": "independent", "group": job["group"], "case": job["case"], "seed": job["seed"], "verdict": ex["verdict"],
           "named": " ".join(named), "run_time_s": ex["run_time_s"], "samples": ex["recording"]["samples"],
           "heldout_outside_support": ex["recording"].get("heldout_outside_support", 0),
           "heldout_samples": ex["recording"]["samples"] - ex["recording"]["training_samples"],
           "magnitude": min([e["magnitude"] for e in truth["effects"]] or [np.nan]),
           "unexplained": " ".join(sorted({u["kind"] + (":" + u["channel"] if u["channel"] else "") for u in ex["unexplained"]}))}
    if planted:
        row["detected"] = all(p in covered or p in absorbed for p in planted)
        row["named_or_absorbed"] = row["detected"]
        row["correct"] = all(p in covered for p in planted)
        row["ambiguous"] = any(p not in named and p in covered for p in planted)
        row["wrong_extra"] = sum(1 for n, alts in named.items() if n not in planted and not (alts & set(planted)))
        for e in truth["effects"]:
            p = PARAMETER.get(e["id"])
            hit = next((x for x in ex["effects"] if x["id"] == e["id"]), None)
            if hit and p in hit["parameters"] and e["id"] == planted[0] and len(planted) == 1:
                row["param_rel_err"] = abs(hit["parameters"][p] - e["value"]) / abs(e["value"])
                ci = hit["confidence"].get(p)
                row["param_covered"] = bool(ci) and ci[0] <= e["value"] <= ci[1]
    for key, confirming in (("heldout_excess_removed", True), ("heldout_excess_removed_all", False)):
        held = heldout_excess(ex, d, confirming, sub)
        if held is not None:
            row[key] = held
    for o in truth["outside"]:
        if "t_step_s" in o:
            row["localised"] = ex["verdict"] == "unexplained_residual" and any(u["kind"] in ("time_window", "change_point", "trend_change") and
                                   u["t_start_s"] - 600.0 <= o["t_step_s"] <= u["t_end_s"] + 600.0 for u in ex["unexplained"])
    return row


def heldout_excess(ex, d, confirming=True, sub="explain"):
    """Fraction of the held-out excess residual (over the generator's own noise there) the refit removed: on
    the held-out samples explain confirms with (heldout == 1), or on every held-out sample, including those
    where the baseline extrapolates outside its training support (heldout == 2)."""
    res_path = os.path.join(d, sub, "residuals.csv")
    if not os.path.exists(res_path):
        return None
    res = np.genfromtxt(res_path, delimiter=",", names=True)
    held = res["heldout"] == 1 if confirming else res["heldout"] > 0
    noise = np.load(os.path.join(d, "noise.npy"))
    floor = float(np.mean(np.square(noise[held] - noise[held].mean())))
    before = float(np.mean(np.square(res["residual_before_dph"][held])))
    after = float(np.mean(np.square(res["residual_after_dph"][held])))
    if before - floor <= 0.05 * floor:  # nothing to remove: the excess is within the noise's own spread
        return None
    return (before - after) / (before - floor)
