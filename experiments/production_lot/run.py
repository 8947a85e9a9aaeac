#!/usr/bin/env python3
"""A production lot (issue 33): does a lot prior learned from 50 units let a 15-min recording calibrate a new unit
as well as its own 62-min dual scan, does `lot screen` find planted defects, and what does a 1,000-unit lot cost?

    /usr/bin/python3 experiments/production_lot/run.py [--gyrosid /tmp/gyrosid-lot] [--parts prior,screen,scale]

Units come from two independent generators (lot_generators.py: A "type draws" around the reference config, B an
independently written family); every unit's config, recordings, models and criteria of fit are cached under
--work, so a rerun only does what is missing.

  prior    per family and lot seed: `lot learn` on 50 training units' dual scans (greybox, shupe=true); for
           --held-out units of the same lot: `calibrate --prior lot.json` on the unit's 15-min recording
           (short_15min.yaml), `calibrate --model greybox` on its own dual scan and (a control) on the 15-min
           recording, each scored by `cof` on the short, medium and long flights with the unit's own config.
  baseline the part of `prior` that needs no lot (today's commands only).
  screen   per family: a lot of --screen-units units with 2 % planted defects (never among the 50 training
           units), `lot learn` on the training units' dual scans, `lot screen` of every unit's 15-min recording.
  scale    family A, --scale-units units from nothing: simulate, learn, calibrate with the prior and screen every
           unit, timed (one process); peak memory of `lot learn` at 50 units and on all units' dual scans.
  design   per family, the lot of --design-lot-seed (1): `design --prior lot.json --model greybox` at --design-budgets (the calibration
           fits with the lot's prior) and `design --evaluate` of the dual scan and the 15-min programme with and without
           it: the predicted criteria of fit. `prior --short-programme <work>/<family>/lot1/design15/trajectory.yaml
           --families <family> --results <dir>` then measures a design on held-out units.

Writes results/summary.json and results/summary.md (the parts run so far).
"""
import argparse
import importlib.util
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "experiments", "lib"))
sys.path.insert(0, HERE)
import gyrosid_experiments as gx  # noqa: E402
import lot_generators as lg  # noqa: E402

FLIGHTS = {"short": [], "medium": [], "long": ["--rate-hz", "10"]}
GREYBOX = {"shupe": True}  # the greybox options of every fit, with or without the lot
PROGRAMMES = {"dual": "builtin:trajectories/dual_scan.yaml", "short": os.path.join(HERE, "short_15min.yaml")}
FAMILY_INDEX = {"A": 1, "B": 2}
CALIBRATIONS = ("prior15", "dual", "short15")  # the lot prior on 15 min; own dual scan; 15 min without the lot
REASON_WORDS = {"shupe_doubled": ("shupe",), "ripple": ("surface", "dsf", "ripple"), "noise_3x": ("noise", "white")}
DPH = np.pi / 180 / 3600  # rad/s per deg/h
ALPHAS = (0.001, 0.01, 0.02, 0.05)  # false-alarm budgets the recall is also read at, from the p-values
SCREEN_SEED = 100  # lot seed of the screening lots (the prior part's lots are 1, 2, ...)
SCALE_SEED = 200


def seeds_of(text):
    """'1-5,8' -> [1, 2, 3, 4, 5, 8]: trajectory_design/seed_sweep.py's parser."""
    spec = importlib.util.spec_from_file_location("seed_sweep", os.path.join(ROOT, "experiments", "trajectory_design", "seed_sweep.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.seeds_of(text)


class Log:
    """Seconds and peak memory of every command that ran, kept beside the products (a rerun keeps the first run's)."""

    def __init__(self, path):
        self.path = path
        self.entries = gx.load_json(path) if os.path.exists(path) else {}

    def record(self, product, seconds, peak_kb=None):
        self.entries[product] = {"s": seconds} if peak_kb is None else {"s": seconds, "peak_kb": peak_kb}

    def get(self, product):
        return self.entries.get(product, {})

    def save(self):
        gx.write_text(self.path, json.dumps(self.entries, indent=0, sort_keys=True))


class Lot:
    """Units `0..n-1` of one family's lot `seed` under work/<family>/lot<seed>/, with their planted defects."""

    def __init__(self, ex, family, seed, defects=None, name=None):
        self.ex, self.family, self.seed = ex, family, seed
        self.generator = lg.GENERATORS[family]()
        self.defects = defects or {}
        self.name = name or "lot%d" % seed  # a lot with defects has its own folder: its units' configs differ
        self.dir = os.path.join(ex.work, family, self.name)

    def unit_path(self, i, *names):
        return self.ex.runner.path(self.family, self.name, "u%05d" % i, *names)

    def sensor(self, i):
        path = self.unit_path(i, "sensor.yaml")
        if not os.path.exists(path):
            truth = lg.write_unit(self.generator, self.seed, i, path, self.defects.get(i))
            gx.write_text(self.unit_path(i, "truth.json"), json.dumps(truth, indent=1))
        return path

    def recording(self, i, programme):
        """The unit's recording of `programme` (dual or short); the noise seed differs per unit and programme (not
        with the short programme's file: another --short-programme has the same noise seeds)."""
        path = self.unit_path(i, self.ex.tagged(programme) + ".csv")
        seed = ((FAMILY_INDEX[self.family] * 1000 + self.seed) * 10000 + i) * 2 + (programme == "short")
        self.ex.run(["simulate", "--sensor", self.sensor(i), "--trajectory", self.ex.programmes[programme], "--seed", seed, "--out", path], path)
        return path

    def learn(self, units, programme="dual", name="lot"):
        """`lot learn` on the units' recordings; the lot file and the command's peak memory."""
        out = os.path.join(self.dir, name, "lot.json")
        recordings = [self.recording(i, programme) for i in units]
        self.ex.run(["lot", "learn", "--recordings"] + recordings + gx.set_args(GREYBOX) + ["--out", out], out, measure_memory=True)
        return out


class Experiment:
    def __init__(self, args):
        self.args = args
        self.work = os.path.abspath(args.work)
        self.runner = gx.Runner(args.gyrosid, self.work, force=args.force)
        self.log = Log(os.path.join(self.work, "log.json"))
        self.ran = 0
        self.programmes = dict(PROGRAMMES, short=os.path.abspath(args.short_programme))
        default = os.path.abspath(PROGRAMMES["short"]) == self.programmes["short"]
        # A design's output is always trajectory.yaml: its folder names it (design10, design15, ...).
        stem = os.path.splitext(os.path.basename(args.short_programme))[0]
        if stem == "trajectory":
            stem = os.path.basename(os.path.dirname(os.path.abspath(args.short_programme))) + "-" + stem
        self.tag = "" if default else "-" + stem

    def tagged(self, name):
        """A product's name: with the short programme's tag when it is made from a 15-min recording."""
        return name + self.tag if name in ("short", "prior15", "short15") else name

    def run(self, argv, product, measure_memory=False):
        """`gyrosid argv` unless `product` exists; logs its seconds (and peak memory, by /usr/bin/time -v)."""
        if os.path.exists(product) and not self.args.force:
            return
        os.makedirs(os.path.dirname(product), exist_ok=True)
        cmd = [self.runner.gyrosid] + [str(a) for a in argv]
        if measure_memory:
            cmd = ["/usr/bin/time", "-v"] + cmd
        start = time.time()
        result = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, GYROSID_QUIET="1"))
        seconds = time.time() - start
        if result.returncode != 0 or not os.path.exists(product):
            sys.stderr.write(result.stdout[-4000:] + result.stderr[-4000:])
            raise RuntimeError("failed: %s" % " ".join(cmd[:12] + (["..."] if len(cmd) > 12 else [])))
        peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", result.stderr) if measure_memory else None
        self.log.record(product, seconds, int(peak.group(1)) if peak else None)
        self.ran += 1
        if self.ran % 50 == 0:
            self.log.save()

    def calibrate(self, lot, i, kind, prior=None):
        """One of CALIBRATIONS of unit i; returns the model file."""
        out = lot.unit_path(i, "%s.json" % self.tagged(kind))
        if kind == "prior15":
            argv = ["calibrate", "--recording", lot.recording(i, "short"), "--prior", prior, "--out", out]
        else:
            rec = lot.recording(i, "dual" if kind == "dual" else "short")
            argv = ["calibrate", "--recording", rec, "--model", "greybox"] + gx.set_args(GREYBOX) + ["--out", out]
        self.run(argv, out)
        return out

    def oracle(self, lot, i):
        """The unit's own truth as a greybox model file: what a perfect calibration of the greybox form would
        compensate. Its criteria of fit are not zero when the unit has a Shupe term: the model compensates it with
        the probe's rate over a +-30 s window, the sensor makes it with the instantaneous rate (a medium-flight
        floor of ~100-200 m that a slightly wrong Shupe coefficient can even undercut)."""
        out = lot.unit_path(i, "oracle.json")
        if os.path.exists(out) and not self.args.force:
            return out
        s = yaml.safe_load(open(lot.sensor(i)))
        model = gx.load_json(self.calibrate(lot, i, "dual"))  # the envelope (features, target, options)
        surface, t = s["scale_factor"]["surface"], s["bias"]["temperature"]
        model["parameters"].update({
            "bias_radps": s["bias"]["constant_dph"] * DPH,
            "bias_temperature_radps": {"reference": t["reference_c"], "coefficients": [c * DPH for c in t["coefficients_dph"]]},
            "scale_factor_surface": {"temperatures_c": surface["temperatures_c"], "rates_radps": [np.deg2rad(r) for r in surface["rates_dps"]],
                                     "values": [[v * 1e-6 for v in row] for row in surface["error_ppm"]], "outside": "clamp"},
            "shupe_rad_per_c": s.get("shupe_dph_per_c_per_min", 0.0) * DPH * 60.0})
        model["summary"] = {"solver": "oracle", "message": "the unit's true error model (run.py)"}
        gx.write_text(out, json.dumps(model, indent=1))
        return out

    def cof(self, lot, i, model, kind):
        """{flight: criterion of fit, m} of a unit's model on its own sensor (noise off; long after 1 h)."""
        row = {}
        for flight, extra in FLIGHTS.items():
            d = lot.unit_path(i, "cof_%s_%s" % (self.tagged(kind), flight), "cof.json")
            self.run(["cof", "--model", model, "--sensor", lot.sensor(i), "--trajectory", flight] + extra + ["--out", os.path.dirname(d)], d)
            j = gx.load_json(d)
            row[flight] = j.get("error_after_1h_m", j["end_error_m"])
        return row

    def screen(self, lot, i, prior, programme="short"):
        out = lot.unit_path(i, "screen_%s" % self.tagged(programme), "screen.json")
        alpha = ["--alpha", str(self.args.alpha)] if self.args.alpha else []
        self.run(["lot", "screen", "--prior", prior, "--recording", lot.recording(i, programme)] + alpha + ["--out", os.path.dirname(out)], out)
        return gx.load_json(out)


# ---------------------------------------------------------------------------------------------------------
# Part 1: the lot prior on held-out units


def prior_part(ex, with_lot=True):
    a = ex.args
    rows = []
    for family in a.families.split(","):
        for seed in seeds_of(a.seeds):
            lot = Lot(ex, family, seed)
            prior = lot.learn(range(a.train)) if with_lot else None
            for i in range(a.train, a.train + a.held_out):
                row = {"family": family, "seed": seed, "unit": i}
                for kind in CALIBRATIONS:
                    if kind == "prior15" and not with_lot:
                        continue
                    row[kind] = ex.cof(lot, i, ex.calibrate(lot, i, kind, prior), kind)
                row["oracle"] = ex.cof(lot, i, ex.oracle(lot, i), "oracle")
                rows.append(row)
                print(json.dumps(row), flush=True)
            ex.log.save()
    return {"short_programme": os.path.relpath(ex.programmes["short"], ROOT), "rows": rows, "aggregate": prior_aggregate(rows, with_lot)}


def geo_mean(x):
    return float(np.exp(np.mean(np.log(x))))


def prior_aggregate(rows, with_lot):
    """Per family and flight: geometric mean of dual-scan cof / 15-min cof (with and without the lot), and the share
    of units where the lot prior on 15 min is at least as good as the dual scan on every flight."""
    out = {}
    for family in sorted({r["family"] for r in rows}):
        fr = [r for r in rows if r["family"] == family]
        agg = {"units": len(fr), "seeds": sorted({r["seed"] for r in fr}), "flights": {}}
        for f in FLIGHTS:
            cell = {"dual_m_geomean": geo_mean([r["dual"][f] for r in fr]), "oracle_m_geomean": geo_mean([r["oracle"][f] for r in fr]),
                    "dual_over_short15": geo_mean([r["dual"][f] / r["short15"][f] for r in fr])}
            if with_lot:
                cell["prior15_m_geomean"] = geo_mean([r["prior15"][f] for r in fr])
                cell["dual_over_prior15"] = geo_mean([r["dual"][f] / r["prior15"][f] for r in fr])
                cell["share_prior15_le_dual"] = float(np.mean([r["prior15"][f] <= r["dual"][f] for r in fr]))
                cell["worst_dual_over_prior15"] = float(min(r["dual"][f] / r["prior15"][f] for r in fr))
            agg["flights"][f] = cell
        if with_lot:
            every = [all(r["prior15"][f] <= r["dual"][f] for f in FLIGHTS) for r in fr]
            agg["share_prior15_le_dual_every_flight"] = float(np.mean(every))
            agg["per_seed_every_flight"] = {s: float(np.mean([e for e, r in zip(every, fr) if r["seed"] == s])) for s in agg["seeds"]}
        out[family] = agg
    return out


# ---------------------------------------------------------------------------------------------------------
# Part 2: screening


def screen_units(ex, lot, prior, n_units):
    """`lot screen` of units 0..n-1 of a lot: one row per unit."""
    units = []
    for i in range(n_units):
        s = ex.screen(lot, i, prior, ex.args.screen_recording)
        units.append({"unit": i, "defect": lot.defects.get(i), "training": i < ex.args.train, "out_of_family": bool(s["out_of_family"]),
                      "p_value": s["p_value"], "reasons": s.get("reasons", [])})
    ex.log.save()
    return units


def defective_lot(ex, family, seed, n_units):
    """Lot `seed` of n units with the planted defects (recorded in the lot's defects.json)."""
    lot = Lot(ex, family, seed, lg.plant_defects(n_units, ex.args.train, ex.args.defect_share, seed), "lot%d_n%d" % (seed, n_units))
    os.makedirs(lot.dir, exist_ok=True)
    gx.write_text(os.path.join(lot.dir, "defects.json"), json.dumps({str(k): v for k, v in lot.defects.items()}, indent=1))
    return lot


def screen_lot(ex, family, seed, n_units):
    lot = defective_lot(ex, family, seed, n_units)
    return screen_units(ex, lot, lot.learn(range(ex.args.train)), n_units)


def reasons_name(defect, reasons, first_only=False):
    text = " ".join(reasons[:1] if first_only else reasons).lower()
    return any(w in text for w in REASON_WORDS[defect])


def screen_aggregate(units):
    out = {"units": len(units), "defects": {}}
    for d in lg.DEFECTS:
        du = [u for u in units if u["defect"] == d]
        flagged = [u for u in du if u["out_of_family"]]
        out["defects"][d] = {"planted": len(du), "flagged": len(flagged), "recall": len(flagged) / len(du) if du else None,
                             "reasons_right": sum(reasons_name(d, u["reasons"]) for u in flagged),
                             "first_reason_right": sum(reasons_name(d, u["reasons"], True) for u in flagged),
                             "units": [{k: u[k] for k in ("unit", "out_of_family", "p_value", "reasons")} for u in du]}
    clean = [u for u in units if u["defect"] is None and not u["training"]]
    train = [u for u in units if u["training"]]
    out["false_alarm_rate"] = float(np.mean([u["out_of_family"] for u in clean])) if clean else None
    out["false_alarms"] = sum(u["out_of_family"] for u in clean)
    out["clean_screened"] = len(clean)
    out["false_alarm_rate_training"] = float(np.mean([u["out_of_family"] for u in train])) if train else None
    out["false_alarm_reasons"] = [u["reasons"] for u in clean if u["out_of_family"]][:20]
    p = np.array([u["p_value"] for u in clean])
    out["clean_p_value_quantiles"] = {q: float(np.quantile(p, float(q))) for q in ("0.01", "0.02", "0.05", "0.1", "0.5")} if len(p) else {}
    all_d = [u for u in units if u["defect"]]
    out["recall_all"] = float(np.mean([u["out_of_family"] for u in all_d])) if all_d else None
    # the same from the p-values at other false-alarm budgets (the flag is p_value < alpha)
    out["by_alpha"] = {str(al): {"recall": {d: float(np.mean([u["p_value"] < al for u in units if u["defect"] == d])) if any(u["defect"] == d for u in units) else None
                                           for d in lg.DEFECTS},
                                 "false_alarm_rate": float(np.mean(p < al)) if len(p) else None} for al in ALPHAS}
    return out


def screen_part(ex):
    out = {}
    for family in ex.args.families.split(","):
        for seed in seeds_of(ex.args.screen_seeds):
            units = screen_lot(ex, family, seed, ex.args.screen_units)
            name = "%s lot %d, %d units, %s recordings" % (family, seed, ex.args.screen_units, "15-min" if ex.args.screen_recording == "short" else "dual-scan")
            out[name] = {"family": family, "seed": seed, **screen_aggregate(units)}
            print(name, "recall", {d: (c["flagged"], c["planted"]) for d, c in out[name]["defects"].items()},
                  "false alarms", out[name]["false_alarms"], "of", out[name]["clean_screened"], flush=True)
    return out


# ---------------------------------------------------------------------------------------------------------
# Part 3: a lot from nothing, timed


def scale_part(ex):
    """Family A lot SCALE_SEED of --scale-units units from nothing (its folder is emptied first unless the timed run
    completed): simulate, learn, calibrate with the prior, screen - one process, timed by stage. Then `lot learn`'s
    peak memory on the training units and on every unit's dual scan."""
    import shutil
    a = ex.args
    n = a.scale_units
    lot = defective_lot(ex, "A", SCALE_SEED, n)
    stamp = os.path.join(ex.work, "pipeline_A_lot%d_%d.json" % (SCALE_SEED, n))
    if not os.path.exists(stamp) or a.force:
        shutil.rmtree(lot.dir)
        lot = defective_lot(ex, "A", SCALE_SEED, n)
        stages, start = {}, time.time()
        for i in range(n):
            lot.recording(i, "short")
        for i in range(a.train):
            lot.recording(i, "dual")
        stages["simulate"] = time.time() - start
        t = time.time()
        prior = lot.learn(range(a.train))
        stages["learn"] = time.time() - t
        t = time.time()
        for i in range(n):
            ex.calibrate(lot, i, "prior15", prior)
        stages["calibrate"] = time.time() - t
        t = time.time()
        screen_units(ex, lot, prior, n)
        stages["screen"] = time.time() - t
        gx.write_text(stamp, json.dumps({"units": n, "wall_s": time.time() - start, "stages_s": stages}, indent=1))
    units = screen_units(ex, lot, lot.learn(range(a.train)), n)
    memory = {}
    for m in sorted({a.train, n} | set(int(x) for x in a.learn_sizes.split(",") if x)):
        out = lot.learn(range(m), name="lot" if m == a.train else "lot_all%d" % m)
        memory[str(m)] = ex.log.get(out)
    ex.log.save()
    return {"pipeline": gx.load_json(stamp), "lot_learn": memory, "screen": {"family": "A", "seed": SCALE_SEED, **screen_aggregate(units)}}


# ---------------------------------------------------------------------------------------------------------
# Part 4: design with the lot prior


def predicted_cof(path, key=None):
    """{flight: predicted criterion of fit, m} from a design.json (key None: the design) or an evaluation.json."""
    j = gx.load_json(path)
    p = j["predicted"] if key is None else j["trajectories"][key]
    return {f: p["flights"][f]["cof_m"] for f in FLIGHTS}


def design_part(ex):
    """Per family, the lot of --design-lot-seed (its 50 training units): `design --prior lot.json --model greybox` at each budget
    (the calibration fits with the lot's prior), and `design --evaluate` of the dual scan and short_15min.yaml for
    the lot's mean unit with and without the prior. Predicted ratios dual scan (own data) / programme (lot prior)."""
    a = ex.args
    out = {}
    for family in a.families.split(","):
        lot = Lot(ex, family, a.design_lot_seed)
        prior = lot.learn(range(a.train))
        fam = {"lot": os.path.relpath(prior, ex.work), "designs": {}, "evaluated": {}}
        for without in (False, True):
            d = os.path.join(lot.dir, "evaluate" + ("_own_data" if without else "_lot_prior"))
            ex.run(["design", "--evaluate", PROGRAMMES["dual"], PROGRAMMES["short"], "--prior", prior, "--model", "greybox"]
                   + (["--without-lot-prior"] if without else []) + ["--out", d], os.path.join(d, "evaluation.json"))
            for name, path in (("dual", PROGRAMMES["dual"]), ("short_15min", PROGRAMMES["short"])):
                fam["evaluated"]["%s, %s" % (name, "own data" if without else "lot prior")] = predicted_cof(os.path.join(d, "evaluation.json"), path)
        dual = fam["evaluated"]["dual, own data"]
        for budget in [float(b) for b in a.design_budgets.split(",")]:
            d = os.path.join(lot.dir, "design%g" % budget)
            product = os.path.join(d, "design.json")
            ex.run(["design", "--prior", prior, "--model", "greybox", "--budget-min", budget, "--seed", 1, "--out", d], product)
            cof = predicted_cof(product)
            fam["designs"]["%g" % budget] = {"trajectory": os.path.relpath(os.path.join(d, "trajectory.yaml"), ex.work), "seconds": ex.log.get(product).get("s"),
                                             "predicted_cof_m": cof, "dual_own_over_design": {f: dual[f] / cof[f] for f in FLIGHTS}}
        short = fam["evaluated"]["short_15min, lot prior"]
        fam["dual_own_over_short15_prior"] = {f: dual[f] / short[f] for f in FLIGHTS}
        reaching = [b for b, r in fam["designs"].items() if all(v >= 1.0 for v in r["dual_own_over_design"].values())]
        fam["shortest_predicted_to_reach_dual"] = min(reaching, key=float) if reaching else None
        out[family] = fam
        print(json.dumps({family: fam}), flush=True)
    return out


def table_design(design):
    lines = ["Predicted criterion of fit (m) for the lot's mean unit; dual scan calibrated by its own data against a programme "
             "calibrated with the lot's prior (ratio > 1: the programme is predicted better).", "",
             "| family | programme | short | medium | long | dual (own) / programme, short / medium / long | design time, s |", "|---" * 7 + "|"]
    for family, fam in design.items():
        for name, cof in fam["evaluated"].items():
            lines.append("| %s | %s | %s | | |" % (family, name, " | ".join("%.3g" % cof[f] for f in FLIGHTS)))
        for budget, r in fam["designs"].items():
            lines.append("| %s | designed %s min, lot prior | %s | %s | %s |" % (
                family, budget, " | ".join("%.3g" % r["predicted_cof_m"][f] for f in FLIGHTS),
                " / ".join("%.2fx" % r["dual_own_over_design"][f] for f in FLIGHTS), "%.0f" % r["seconds"] if r["seconds"] else "-"))
        lines.append("| %s | short_15min.yaml, lot prior | | | | %s | |" % (family, " / ".join("%.2fx" % v for v in fam["dual_own_over_short15_prior"].values())))
    lines.append("")
    for family, fam in design.items():
        lines.append("Family %s: shortest designed budget predicted to reach the dual scan on every flight: %s." % (
            family, "%s min" % fam["shortest_predicted_to_reach_dual"] if fam["shortest_predicted_to_reach_dual"] else "none of those tried"))
    return lines


# ---------------------------------------------------------------------------------------------------------
# Summary


def table_prior(prior):
    lines = ["15-min programme: `%s`." % prior.get("short_programme", "experiments/production_lot/short_15min.yaml"), "","| family | flight | dual scan, m (geo. mean) | lot prior on 15 min, m | dual / prior-15 | share prior-15 <= dual | worst dual / prior-15 | "
             "dual / 15 min without lot | the truth as a greybox model, m |", "|---" * 9 + "|"]
    for family, agg in prior["aggregate"].items():
        for f, c in agg["flights"].items():
            lines.append("| %s | %s | %.3g | %s | %s | %s | %s | %.2fx | %.3g |" % (
                family, f, c["dual_m_geomean"], "%.3g" % c["prior15_m_geomean"] if "prior15_m_geomean" in c else "-",
                "%.2fx" % c["dual_over_prior15"] if "dual_over_prior15" in c else "-",
                "%.0f %%" % (100 * c["share_prior15_le_dual"]) if "share_prior15_le_dual" in c else "-",
                "%.2fx" % c["worst_dual_over_prior15"] if "worst_dual_over_prior15" in c else "-", c["dual_over_short15"], c["oracle_m_geomean"]))
    lines.append("")
    for family, agg in prior["aggregate"].items():
        if "share_prior15_le_dual_every_flight" in agg:
            lines.append("Family %s: %d held-out units over seeds %s; the lot prior on 15 min is at least as good as the dual scan on "
                         "every flight for %.0f %% of units (per seed: %s)." % (
                             family, agg["units"], agg["seeds"], 100 * agg["share_prior15_le_dual_every_flight"],
                             ", ".join("%s: %.0f %%" % (s, 100 * v) for s, v in agg["per_seed_every_flight"].items())))
    return lines


def table_screen(screen):
    lines = ["At the command's default alpha (`out_of_family`); in brackets, of the flagged units, those whose first (largest) "
             "reason names the defect / those where any reason does (shupe / the surface / the noise):", "",
             "| lot | " + " | ".join("%s recall" % d for d in lg.DEFECTS) + " | all defects | false alarms (clean, not training) | training units flagged |",
             "|---" * (4 + len(lg.DEFECTS)) + "|"]
    for name, s in screen.items():
        cells = []
        for d in lg.DEFECTS:
            c = s["defects"][d]
            cells.append("%d/%d (%d / %d)" % (c["flagged"], c["planted"], c["first_reason_right"], c["reasons_right"]) if c["planted"] else "-")
        lines.append("| %s | %s | %s | %d/%d = %.1f %% | %s |" % (
            name, " | ".join(cells), "%.0f %%" % (100 * s["recall_all"]) if s["recall_all"] is not None else "-",
            s["false_alarms"], s["clean_screened"], 100 * s["false_alarm_rate"],
            "%.0f %%" % (100 * s["false_alarm_rate_training"]) if s["false_alarm_rate_training"] is not None else "-"))
    lines += ["", "Read from the p-values at other alphas (flag: p < alpha):", "",
              "| lot | alpha | " + " | ".join("%s recall" % d for d in lg.DEFECTS) + " | false-alarm rate |", "|---" * (3 + len(lg.DEFECTS)) + "|"]
    for name, s in screen.items():
        for al, c in s.get("by_alpha", {}).items():
            lines.append("| %s | %s | %s | %.1f %% |" % (name, al, " | ".join("-" if c["recall"][d] is None else "%.0f %%" % (100 * c["recall"][d])
                                                                            for d in lg.DEFECTS), 100 * c["false_alarm_rate"]))
    lines += ["", "Reasons given for the planted defects (first three of each type per lot):", ""]
    for name, s in screen.items():
        for d in lg.DEFECTS:
            for u in s["defects"][d]["units"][:3]:
                lines.append("- %s, unit %d (%s): %s, p = %.3g, reasons: %s" % (
                    name, u["unit"], d, "flagged" if u["out_of_family"] else "not flagged", u["p_value"], "; ".join(u["reasons"]) or "-"))
    return lines


def table_scale(scale):
    p = scale["pipeline"]
    lines = ["%d-unit lot (family A) from nothing, one process: %.0f s wall (%s)." % (
        p["units"], p["wall_s"], ", ".join("%s %.0f s" % kv for kv in p["stages_s"].items()))]
    for units, m in sorted(scale["lot_learn"].items(), key=lambda kv: int(kv[0])):
        if m:
            lines.append("`lot learn` on %s units' dual scans: %.1f s, peak %.0f MB." % (units, m["s"], m.get("peak_kb", 0) / 1024))
    return lines


def write_summary(summary, results):
    os.makedirs(results, exist_ok=True)
    gx.write_text(os.path.join(results, "summary.json"), json.dumps(summary, indent=1, default=str))
    lines = ["# production_lot results", "", "gyrosid: `%s`" % summary.get("gyrosid", ""), ""]
    for key, title, fn in (("prior", "Lot prior on held-out units (criterion of fit, noise off, long after 1 h)", table_prior),
                           ("baseline", "Baselines without a lot", table_prior),
                           ("screen", "Screening", table_screen), ("scale", "Cost", table_scale),
                           ("design", "Design with the lot prior", table_design)):
        if key in summary:
            lines += ["## " + title, ""] + fn(summary[key]) + [""]
    gx.write_text(os.path.join(results, "summary.md"), "\n".join(lines))
    print("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gyrosid", default="/tmp/gyrosid-lot")
    ap.add_argument("--work", default="/tmp/gyrosid-production-lot")
    ap.add_argument("--parts", default="prior,screen,scale", help="comma list of baseline, prior, screen, scale, design")
    ap.add_argument("--families", default="A,B")
    ap.add_argument("--seeds", default="1-5", help="lot seeds of the prior part")
    ap.add_argument("--train", type=int, default=50, help="training units of every lot")
    ap.add_argument("--held-out", type=int, default=10, help="held-out units per lot (prior part)")
    ap.add_argument("--screen-units", type=int, default=200)
    ap.add_argument("--screen-seeds", default=str(SCREEN_SEED))
    ap.add_argument("--screen-recording", default="short", choices=sorted(PROGRAMMES))
    ap.add_argument("--short-programme", default=PROGRAMMES["short"], help="the production recording's programme (default: %(default)s)")
    ap.add_argument("--defect-share", type=float, default=0.02)
    ap.add_argument("--alpha", type=float, default=None, help="lot screen --alpha (default: the command's)")
    ap.add_argument("--scale-units", type=int, default=1000)
    ap.add_argument("--learn-sizes", default="", help="more lot sizes (comma list) whose `lot learn` memory the scale part measures")
    ap.add_argument("--results", default=os.path.join(HERE, "results"), help="where summary.json/.md go (default: %(default)s)")
    ap.add_argument("--design-budgets", default="5,10,15", help="budgets (min, comma list) of the design part")
    ap.add_argument("--design-lot-seed", type=int, default=1, help="the lot (seed) the design part designs for")
    ap.add_argument("--force", action="store_true")
    a = ap.parse_args()
    ex = Experiment(a)
    path = os.path.join(a.results, "summary.json")
    summary = gx.load_json(path) if os.path.exists(path) else {}
    summary["gyrosid"] = a.gyrosid
    parts = a.parts.split(",")
    if "baseline" in parts:
        summary["baseline"] = prior_part(ex, with_lot=False)
    if "prior" in parts:
        summary["prior"] = prior_part(ex)
    if "screen" in parts:
        summary.setdefault("screen", {}).update(screen_part(ex))
    if "scale" in parts:
        summary["scale"] = scale_part(ex)
        summary.setdefault("screen", {})["A lot %d, %d units, %s recordings (the timed lot)" % (
            SCALE_SEED, a.scale_units, "15-min" if a.screen_recording == "short" else "dual-scan")] = summary["scale"]["screen"]
    if "design" in parts:
        summary["design"] = design_part(ex)
    ex.log.save()
    write_summary(summary, a.results)


if __name__ == "__main__":
    main()
