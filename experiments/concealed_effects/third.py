#!/usr/bin/python3
"""A third, independent generator for the concealed-effects experiment (issue 34), and its driver.

Recordings written here from first principles (numpy/scipy only), unlike both gyrosid's simulator and the
second generator (independent.py) in every part:

* sensor - a 10-Hz gyro averaged to 1 Hz (block means of ten samples). The bias is a linear term plus a tanh in
  the die temperature, the scale-factor error an exponential in temperature plus a quadratic in rate (ppm). The
  10-Hz output is quantised (LSB 0.005 deg/s = 18 deg/h), then averaged. Noise: white (19 deg/h per 10-Hz
  sample) plus a flicker-like bias instability, the sum of four Gauss-Markov processes at 20, 200, 2,000 and
  20,000 s (0.25 deg/h each). The white noise per 1-Hz sample, quantisation included, is SIGMA_DPH (6.2 deg/h).
* temperatures - the die follows the chamber through a second-order lag (two poles, 60 s and 240 s); the probe
  reads the die with 0.02 C of noise and a 12-bit quantisation (0.0625 C), not 0.01 C.
* thermal programmes - a sine (35 C amplitude, 2.4-h period), a staircase of chamber steps (20 C .. 65 C ..
  -15 C .. 25 C, 35-min levels), a soak-then-ramp (-25 C soak, 0.5 C/min to 65 C, a fast return); 6.0-6.75 h.
* rate programmes - constant-rate dwells of 120 s with reversals (0, +-15, +-50, +-100, +-150 deg/s), or a
  random rate-table dwell sequence (rates -150..150 deg/s in 10s, dwells 40-300 s, 20 deg/s^2 transitions).
* effect forms explain has not seen (`EFFECTS`): two play operators of 0.5 and 4 C, and a smooth
  exponential-in-travel (Duhem) loop, for thermal_hysteresis; a stretched-exponential and a power-law warm-up;
  logarithmic ageing; Shupe through a radial gradient (the die minus its own 400-s lag); a scale-factor
  asymmetry with a tanh transition near zero rate; a Gaussian temperature bump of the bias; a two-pole lag
  between the probe and the coil. Outside the library (`OUTSIDE`): a bias quadratic in a 12-V supply voltage,
  a bias step with an exponential recovery to 30 %, a quadratic drift setting in at a drawn time (10-90 %).

An effect's size: the RMS of the part the baseline family explain fits without a simulation cannot absorb
(independent.baseline_columns on the recorded temperature and rate; measurement, not physics), in units of
SIGMA_DPH. The lag is a real two-pole lag whose time constant is found by bisection to give the asked size.
Self-check (every recording): the recording is read back, the known base sensor and noise are removed, and the
unabsorbed RMS of what is left must equal the asked magnitude (single effects, within 2 %); the base sensor's
own unabsorbed part is stored (it is the part a control could mistake for missing physics).

Right: a library effect named (or in a named effect's alternatives); supply_quadratic `unexplained_residual`
following supply_v; the recovering step and the drift `unexplained_residual` localised (change point, trend
change or time window) within 600 s of the onset; a control `no_missing_physics`. explain gets no simulation and
no options but --seed, one thread.

    third.py --gyrosid /tmp/g3/gyrosid-d9cee4e --tag d9cee4e --out /tmp/g3/third [--seeds 2] [--budget-min 40]
             [--csv results/third_d9cee4e.csv] [--md results/third.md]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.signal import lfilter

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import independent as ind  # noqa: E402  (baseline_columns, unabsorbed: the sizing, not the physics)
import independent_cases as ic  # noqa: E402  (heldout_excess, named_and_alternatives, save_case)
from gyrosid_experiments import add_gyrosid_argument  # noqa: E402

FS = 10                       # internal rate (Hz); recorded as block means of FS samples at 1 Hz
WHITE_10HZ_DPH = 19.0         # white noise per 10-Hz sample
GYRO_LSB_DPS = 0.005          # 10-Hz output quantisation (18 deg/h)
FLICKER_TAUS_S = (20.0, 200.0, 2000.0, 20000.0)
FLICKER_SIGMA_DPH = 0.25      # each of the four Gauss-Markov processes
DIE_TAUS_S = (60.0, 240.0)    # chamber -> die, two poles
PROBE_NOISE_C, PROBE_LSB_C = 0.02, 0.0625
SIGMA_DPH = math.sqrt(WHITE_10HZ_DPH ** 2 + (GYRO_LSB_DPS * 3600.0) ** 2 / 12.0) / math.sqrt(FS)  # per 1-Hz sample

# Noise variants (the controls draw each): flicker x3; a coarser gyro LSB (0.01 deg/s) and probe (0.25 C).
NOISE = {"base": {}, "flicker_strong": {"flicker_scale": 3.0}, "coarse_quant": {"gyro_lsb_dps": 0.01, "probe_lsb_c": 0.25}}

# effect -> the explain id it should be named as
EFFECTS = {"hyst_two_plays": "thermal_hysteresis", "hyst_smooth": "thermal_hysteresis", "warmup_stretched": "warmup_transient",
           "warmup_power": "warmup_transient", "ageing_log": "aging_trend", "shupe_gradient": "shupe",
           "asym_smooth": "scale_factor_asymmetry", "tbias_bump": "temperature_bias", "lag_two_pole": "thermal_lag"}
OUTSIDE = {"supply_quadratic": "follows_channel:supply_v", "step_recovery": "localised", "drift_odd": "localised"}
COMBINATIONS = {"hyst_smooth+ageing_log": ["hyst_smooth", "ageing_log"], "shupe_gradient+asym_smooth": ["shupe_gradient", "asym_smooth"],
                "warmup_stretched+tbias_bump": ["warmup_stretched", "tbias_bump"]}
MAGNITUDES = (0.5, 1.0)
LOCALISING = ("time_window", "change_point", "trend_change")


# ---------------------------------------------------------------- programmes (10 Hz)
def chamber(name, seed):
    """Chamber air temperature (C) at FS Hz along a programme."""
    dt = 1.0 / FS
    if name == "sine":
        t = np.arange(0.0, 22680.0, dt)  # 30-min hold, then 2.4 cycles of a 2.4-h sine
        return t, np.where(t < 1800.0, 20.0, 20.0 + 35.0 * np.sin(2 * math.pi * (t - 1800.0) / 8640.0))
    if name == "staircase":  # chamber steps slewed at 3 C/min, 35-min levels
        levels = [20, 35, 50, 65, 45, 25, 5, -15, 5, 25]
        kt, kv = [0.0, 2100.0], [20.0, 20.0]
        for lv in levels[1:]:
            kt += [kt[-1] + abs(lv - kv[-1]) / 3.0 * 60.0]
            kv += [lv]
            kt += [kt[-1] + 2100.0]
            kv += [lv]
    elif name == "soak_ramp":  # soak cold, one slow ramp up, a fast return
        kt, kv = [0.0, 1200.0], [20.0, 20.0]
        for target, rate, hold in ((-25, 2.0, 60), (65, 0.5, 30), (20, 1.5, 20)):
            kt += [kt[-1] + abs(target - kv[-1]) / rate * 60.0, 0.0]
            kt[-1] = kt[-2] + hold * 60.0
            kv += [target, target]
    else:
        raise KeyError(name)
    t = np.arange(0.0, kt[-1], dt)
    return t, np.interp(t, kt, kv)


def rate_programme(name, t, seed):
    """Table rate (deg/s) at FS Hz: dwells joined by constant-acceleration (20 deg/s^2) transitions."""
    rng = np.random.default_rng([seed, 5])
    kt, kv = [0.0], [0.0]
    if name == "dwells":
        seq = [0, 15, -15, 50, -50, 100, -100, 150, -150, 100, -100, 50, -50, 15, -15]
        k = 0
        while kt[-1] < t[-1]:
            r = seq[k % len(seq)]
            kt += [kt[-1] + abs(r - kv[-1]) / 20.0 + 0.1, 0.0]
            kt[-1] = kt[-2] + 120.0
            kv += [r, r]
            k += 1
    elif name == "random_table":
        while kt[-1] < t[-1]:
            r = float(rng.choice(np.arange(-150, 151, 10)))
            kt += [kt[-1] + abs(r - kv[-1]) / 20.0 + 0.1, 0.0]
            kt[-1] = kt[-2] + rng.uniform(40.0, 300.0)
            kv += [r, r]
    else:
        raise KeyError(name)
    return np.interp(t, kt, kv)


def lag1(x, tau, dt=1.0 / FS):
    """x through dy/dt = (x - y)/tau (exact for x held over a step), from equilibrium."""
    a = math.exp(-dt / tau)
    return lfilter([1 - a], [1, -a], x, zi=[a * x[0]])[0]


def gauss_markov(n, sigma, tau, rng, dt=1.0 / FS):
    a = math.exp(-dt / tau)
    w = rng.normal(0, sigma * math.sqrt(1 - a * a), n)
    return lfilter([1.0], [1, -a], w, zi=[a * rng.normal(0, sigma)])[0]


def supply_voltage(t, rng):
    """A 12-V supply: an Ornstein-Uhlenbeck wander (80 mV, 20 min) and three load steps of 60-150 mV."""
    v = 12.0 + gauss_markov(len(t), 0.08, 1200.0, rng)
    for frac in np.sort(rng.uniform(0.1, 0.9, 3)):
        v[t >= frac * t[-1]] += rng.uniform(0.06, 0.15) * rng.choice([-1.0, 1.0])
    return v


# ---------------------------------------------------------------- sensor law (deg/h)
def base_error_dph(temp, w):
    """Bias (linear + tanh in temperature) plus scale-factor error (exponential in T, quadratic in rate)."""
    bias = 4.0 + 0.6 * (temp - 20.0) + 6.0 * np.tanh((temp - 20.0) / 45.0)
    sf_ppm = 120.0 + 40.0 * np.exp((temp - 20.0) / 60.0) + 15.0 * (w / 150.0) ** 2
    return bias + sf_ppm * 1e-6 * w * 3600.0


def play(x, r):
    y = np.empty_like(x)
    y[0] = x[0]
    lo, hi = x - r, x + r
    prev = x[0]
    for i in range(1, len(x)):
        prev = min(max(prev, lo[i]), hi[i])
        y[i] = prev
    return y


def duhem(x, width):
    """A smooth loop: y moves towards sign(dx) by exp(-|dx| / width) of the way at each step (y in [-1, 1])."""
    y = np.empty_like(x)
    dx = np.diff(x, prepend=x[0])
    decay = np.exp(-np.abs(dx) / width)
    s = np.sign(dx)
    prev = 0.0
    for i in range(len(x)):
        if s[i] != 0:
            prev = s[i] + (prev - s[i]) * decay[i]
        y[i] = prev
    return y


def shape(effect, s):
    """An effect at unit size (deg/h) on the 10-Hz arrays of s."""
    t, die, w = s["t"], s["die"], s["w"]
    if effect == "hyst_two_plays":   # weights 0.3 / 0.7; each play's term saturates at +-0.5
        return sum(k * (die - play(die, r)) / (2 * r) for r, k in ((0.5, 0.3), (4.0, 0.7)))
    if effect == "hyst_smooth":
        return 0.5 * duhem(die, 2.5)
    if effect == "warmup_stretched":
        return np.exp(-(t / 1500.0) ** 0.5)
    if effect == "warmup_power":
        return (1.0 + t / 400.0) ** -1.5
    if effect == "ageing_log":
        return np.log1p(t / 3000.0)
    if effect == "shupe_gradient":   # the coil's outer layers lead its core by a 400-s lag
        return die - lag1(die, 400.0)
    if effect == "asym_smooth":      # 1 ppm between the senses away from zero, a tanh over +-4 deg/s
        return 0.5 * w * np.tanh(w / 4.0) * 3600.0 * 1e-6
    if effect == "tbias_bump":       # a resonance of the bias near 32 C
        return np.exp(-((die - 32.0) / 8.0) ** 2)
    if effect == "supply_quadratic":
        return (s["supply_v"] - 11.7) ** 2
    if effect == "step_recovery":
        dt = np.maximum(t - s["t_on"], 0.0)
        return (t >= s["t_on"]) * (0.3 + 0.7 * np.exp(-dt / 1800.0))
    if effect == "drift_odd":
        return (np.maximum(t - s["t_on"], 0.0) / 3600.0) ** 2
    raise KeyError(effect)


def lag_signal(s, tau):
    """The base law on a coil two poles (tau each) behind the die, minus the law on the die."""
    coil = lag1(lag1(s["die"], tau), tau)
    return base_error_dph(coil, s["w"]) - base_error_dph(s["die"], s["w"])


def mean1hz(x):
    return x[:len(x) // FS * FS].reshape(-1, FS).mean(axis=1)


# ---------------------------------------------------------------- one recording
PROGRAMMES = ("sine", "staircase", "soak_ramp")
RATES = ("dwells", "random_table")


def make_recording(spec, seed):
    """spec: {"effects": [{"id", "magnitude"}], "noise": variant}. Returns cols, truth, noise (deg/h, 1 Hz)."""
    rng = np.random.default_rng(seed)
    programme, rates = PROGRAMMES[seed % 3], RATES[(seed // 3) % 2]
    nv = dict(NOISE[spec.get("noise", "base")])
    t10, ch = chamber(programme, seed)
    die = lag1(lag1(ch, DIE_TAUS_S[0]), DIE_TAUS_S[1])
    w = rate_programme(rates, t10, seed)
    s = {"t": t10, "die": die, "w": w, "supply_v": supply_voltage(t10, rng)}
    n1 = len(t10) // FS
    t1 = np.arange(n1, dtype=float)
    probe_lsb = nv.get("probe_lsb_c", PROBE_LSB_C)
    probe = np.round((mean1hz(die) + rng.normal(0, PROBE_NOISE_C, n1)) / probe_lsb) * probe_lsb
    ref = mean1hz(w)
    x_base = ind.baseline_columns(probe, ref)
    truth = {"programme": programme, "rates": rates, "noise": spec.get("noise", "base"), "effects": [], "outside": []}
    base = base_error_dph(die, w)
    truth["base_unabsorbed_sigma"] = ind.rms(ind.unabsorbed(x_base, mean1hz(base))) / SIGMA_DPH
    planted = np.zeros_like(t10)
    for e in spec.get("effects", []):
        eid, m = e["id"], e["magnitude"]
        rec = {"id": EFFECTS.get(eid, eid), "form": eid, "magnitude": m}
        if eid in ("step_recovery", "drift_odd"):
            s["t_on"] = float(rng.uniform(0.3, 0.7) if eid == "step_recovery" else rng.uniform(0.1, 0.9)) * t10[-1]
            rec["t_step_s"] = s["t_on"]
        if eid == "lag_two_pole":
            lo, hi = 1.0, 3000.0  # bisection on tau (log scale) for the asked unabsorbed rms
            size = lambda tau: ind.rms(ind.unabsorbed(x_base, mean1hz(lag_signal(s, tau)))) / SIGMA_DPH  # noqa: E731
            for _ in range(30):
                mid = math.sqrt(lo * hi)
                lo, hi = (mid, hi) if size(mid) < m else (lo, mid)
            tau = math.sqrt(lo * hi)
            v = lag_signal(s, tau)
            rec.update(tau_s_per_pole=tau, value=2 * tau, achieved=size(tau))
            if rec["achieved"] < 0.98 * m:  # the programme cannot show a lag this large below tau = 3000 s a pole
                rec.update(magnitude=rec["achieved"], asked=m, capped=True)
            planted += v
        else:
            v = shape(eid, s)
            c = m * SIGMA_DPH / ind.rms(ind.unabsorbed(x_base, mean1hz(v)))
            rec["value"] = c
            planted += c * v
        (truth["effects"] if eid in EFFECTS else truth["outside"]).append(rec)
    # Noise at 10 Hz: white plus the four Gauss-Markov processes; the output quantised, then averaged.
    noise10 = rng.normal(0, WHITE_10HZ_DPH, len(t10))
    for tau in FLICKER_TAUS_S:
        noise10 += gauss_markov(len(t10), FLICKER_SIGMA_DPH * nv.get("flicker_scale", 1.0), tau, rng)
    clean10 = w + (base + planted) / 3600.0
    lsb = nv.get("gyro_lsb_dps", GYRO_LSB_DPS)
    gyro10 = np.round((clean10 + noise10 / 3600.0) / lsb) * lsb
    gyro = mean1hz(gyro10)
    noise = (gyro - mean1hz(clean10)) * 3600.0
    cols = {"t_s": t1, "ref_rate_dps": ref, "temp_c": probe, "gyro_dps": gyro, "chamber_temp_c": np.round(mean1hz(ch), 1),
            "supply_v": np.round(mean1hz(s["supply_v"]), 3)}
    truth["planted_unabsorbed_dph"] = ind.unabsorbed(x_base, mean1hz(planted))
    return {"cols": cols, "truth": truth, "noise_dph": noise, "base_1hz": mean1hz(base)}


def self_check(cols, r, spec):
    """Reads nothing from the generator's internals but the known base law and the noise: what is left of the
    written columns must be the planted effect at its asked size."""
    left = (cols["gyro_dps"] - cols["ref_rate_dps"]) * 3600.0 - r["noise_dph"] - r["base_1hz"]
    got = ind.rms(ind.unabsorbed(ind.baseline_columns(cols["temp_c"], cols["ref_rate_dps"]), left)) / SIGMA_DPH
    effects = r["truth"]["effects"] + r["truth"]["outside"]
    if len(effects) == 1:
        want = effects[0]["magnitude"]  # as planted (a lag capped at 3000 s a pole: the size it reached)
        if abs(got - want) > 0.02 * want:
            raise AssertionError("planted %s: unabsorbed %.4f sigma, asked %.4f" % (effects[0]["id"], got, want))
    elif not effects and got > 1e-6:
        raise AssertionError("control: %.3g sigma left besides base and noise" % got)
    return got


def jobs(out, seeds):
    def job(group, case, seed, spec):
        return {"group": group, "case": case, "seed": seed, "spec": spec, "dir": os.path.join(out, group, case.replace("+", "_"), "seed%d" % seed)}
    rounds = []
    for k in range(seeds):
        r = []
        for i, e in enumerate(EFFECTS):
            for m in MAGNITUDES:
                r.append(job("effect", "%s@%s" % (e, m), 31000 + 100 * i + int(10 * m) + k, {"effects": [{"id": e, "magnitude": m}]}))
        for i, e in enumerate(OUTSIDE):
            for m in MAGNITUDES:
                r.append(job("outside", "%s@%s" % (e, m), 32000 + 100 * i + int(10 * m) + k, {"effects": [{"id": e, "magnitude": m}]}))
        if k == 0:
            for i, (name, es) in enumerate(COMBINATIONS.items()):
                for m in MAGNITUDES:
                    r.append(job("combination", "%s@%s" % (name, m), 33000 + 100 * i + int(10 * m), {"effects": [{"id": e, "magnitude": m} for e in es]}))
        rounds.append(r)
    controls = [job("control", "nothing_missing_%s" % v, 34000 + 10 * i + j, {"noise": v}) for j in range(4) for i, v in enumerate(NOISE)]
    # Controls first (all 12), then every case's first seed, then the second seeds: a run cut short covers every case.
    return controls + [j for r in rounds for j in r]


def build(job):
    d = job["dir"]
    truth_path = os.path.join(d, "truth.json")
    if os.path.exists(truth_path):
        return json.load(open(truth_path))
    os.makedirs(d, exist_ok=True)
    r = make_recording(job["spec"], job["seed"])
    r["truth"]["check_unabsorbed_sigma"] = self_check(r["cols"], r, job["spec"])
    meta = ["# format: gyrosid-recording/1\n",
            "# sensor: 10-Hz gyro averaged to 1 Hz, written by experiments/concealed_effects/third.py (not gyrosid's simulator)\n",
            "# description: %s, seed %d, programme %s, rates %s, noise %s\n" % (job["case"], job["seed"], r["truth"]["programme"],
                                                                          r["truth"]["rates"], r["truth"]["noise"]),
            "# sample_rate_hz: 1\n"]
    return ic.save_case(d, meta, r)


def score(job, truth, ex, d, tag):
    named = ic.named_and_alternatives(ex)
    covered = set(named) | {a for alts in named.values() for a in alts}
    planted = [e["id"] for e in truth["effects"]]
    row = {"group": job["group"], "case": job["case"], "seed": job["seed"], "programme": truth["programme"], "rates": truth["rates"],
           "noise": truth["noise"], "truth": " ".join([e["id"] for e in truth["effects"]] + [o["id"] for o in truth["outside"]]) or "nothing",
           "verdict": ex["verdict"], "named": " ".join(named),
           "unexplained": " ".join("%s[%.0f,%.0f]" % (u["kind"], u.get("t_start_s", 0), u.get("t_end_s", 0)) if u["kind"] in LOCALISING
                                   else u["kind"] + (":" + u["channel"] if u.get("channel") else "") for u in ex["unexplained"]),
           "noise_terms": " ".join(x["id"] for x in ex["noise"]["terms"]), "run_time_s": ex["run_time_s"], "samples": ex["recording"]["samples"],
           "base_unabsorbed_sigma": round(truth["base_unabsorbed_sigma"], 4), "check_unabsorbed_sigma": round(truth["check_unabsorbed_sigma"], 4)}
    lib_names = set(named)
    if job["group"] == "control":
        row["correct"] = ex["verdict"] == "no_missing_physics"
    elif planted:
        row["correct"] = all(p in covered for p in planted)
        row["wrong_extra"] = sum(1 for n, alts in named.items() if n not in planted and not (alts & set(planted)))
    else:
        o = truth["outside"][0]
        row["wrong_extra"] = len(lib_names)
        if "t_step_s" in o:
            row["t_on_s"] = round(o["t_step_s"])
            row["localised"] = ex["verdict"] == "unexplained_residual" and any(
                u["kind"] in LOCALISING and min(abs(u["t_start_s"] - o["t_step_s"]), abs(u["t_end_s"] - o["t_step_s"])) <= 600.0
                for u in ex["unexplained"])
        else:
            row["localised"] = ex["verdict"] == "unexplained_residual" and any(
                u["kind"] == "follows_channel" and u.get("channel") == "supply_v" for u in ex["unexplained"])
        row["correct"] = row["localised"]
    lag = next((e for e in truth["effects"] if e["form"] == "lag_two_pole"), None)
    if lag:
        row["lag_tau_s_per_pole"] = round(lag["tau_s_per_pole"], 1)
        row["planted_sigma"] = round(lag["magnitude"], 3)
    held = ic.heldout_excess(ex, d, True, tag)
    if held is not None:
        row["heldout_excess_removed"] = round(held, 3)
    return row


COLUMNS = ["group", "case", "seed", "programme", "rates", "noise", "truth", "verdict", "named", "unexplained", "correct", "wrong_extra",
           "localised", "t_on_s", "heldout_excess_removed", "noise_terms", "lag_tau_s_per_pole", "planted_sigma", "base_unabsorbed_sigma",
           "check_unabsorbed_sigma", "samples", "run_time_s"]


def md_summary(rows, cmd, binary):
    def cell(r):
        return "%s%s%s" % (r["verdict"], " (" + r["named"] + ")" if r["named"] else "", " " + r["unexplained"] if r["unexplained"] else "")
    out = ["# Concealed effects: the third generator\n\n",
           "Written by `experiments/concealed_effects/third.py` (its docstring: the sensor, programmes, noise and effect forms). "
           "Binary %s; command:\n\n```\n%s\n```\n\n" % (binary, cmd),
           "Per-sample white noise sigma %.2f deg/h (1 Hz, quantisation included). Right: a library effect named (or in a named "
           "effect's alternatives); outside the library `unexplained_residual` localised within 600 s of the onset or following "
           "supply_v; a control `no_missing_physics`. Run times were measured with one explain at a time, one thread, niced, "
           "**beside another engineer's C++ build** on a 2-core machine.\n\n" % SIGMA_DPH]
    for group, title in (("effect", "Single effects (library)"), ("outside", "Outside the library"), ("combination", "Two-effect combinations"),
                         ("control", "Controls (nothing planted)")):
        g = [r for r in rows if r["group"] == group]
        if not g:
            continue
        ok = sum(1 for r in g if r["correct"])
        out.append("## %s: %d/%d right\n\n" % (title, ok, len(g)))
        out.append("| case | seed | programme / rates / noise | truth | right | wrong extra | held-out excess removed | explain said | time (s) |\n|---|---|---|---|---|---|---|---|---|\n")
        for r in g:
            out.append("| %s | %d | %s / %s / %s | %s | %s | %s | %s | %s | %.1f |\n" % (
                r["case"] + (" (tau %s s/pole, %s sigma)" % (r["lag_tau_s_per_pole"], r["planted_sigma"]) if r.get("lag_tau_s_per_pole") else "") +
                (" (onset %s s)" % r["t_on_s"] if r.get("t_on_s") is not None else ""), r["seed"], r["programme"], r["rates"],
                r["noise"], r["truth"], "yes" if r["correct"] else "**no**", r.get("wrong_extra", ""), r.get("heldout_excess_removed", "-"),
                cell(r), r["run_time_s"]))
        out.append("\n")
    eff = [r for r in rows if r["group"] == "effect"]
    if eff:
        out.append("## Per effect form\n\n| form | explain id | 0.5 sigma | 1.0 sigma | wrong extra names |\n|---|---|---|---|---|\n")
        for form, eid in EFFECTS.items():
            cells = []
            for m in MAGNITUDES:
                g = [r for r in eff if r["case"] == "%s@%s" % (form, m)]
                cells.append("%d/%d" % (sum(r["correct"] for r in g), len(g)) if g else "-")
            extra = sum(r.get("wrong_extra", 0) for r in eff if r["case"].startswith(form + "@"))
            out.append("| %s | %s | %s | %s | %d |\n" % (form, eid, cells[0], cells[1], extra))
        out.append("\n")
    ctrl = [r for r in rows if r["group"] == "control"]
    times = sorted(r["run_time_s"] for r in rows)
    out.append("## Summary\n\n")
    out.append("- controls: %d/%d false discoveries\n" % (sum(1 for r in ctrl if not r["correct"]), len(ctrl)))
    for group in ("effect", "outside", "combination"):
        g = [r for r in rows if r["group"] == group]
        if g:
            ex = sorted(r["heldout_excess_removed"] for r in g if r["correct"] and r.get("heldout_excess_removed") is not None)
            out.append("- %s: %d/%d right, %d with a wrong extra name%s\n" % (group, sum(r["correct"] for r in g), len(g),
                       sum(1 for r in g if r.get("wrong_extra")), "; held-out excess removed (right ones) median %.3f / min %.3f" % (
                           float(np.median(ex)), ex[0]) if ex else ""))
    if times:
        out.append("- run time (s): median %.1f, max %.1f over %d recordings (beside a C++ build)\n" % (float(np.median(times)), times[-1], len(times)))
    base = [r["base_unabsorbed_sigma"] for r in rows]
    out.append("- the base sensor's own unabsorbed part: max %.4f sigma\n" % max(base))
    return "".join(out)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_gyrosid_argument(p)
    p.add_argument("--tag", required=True, help="name of this binary's results (a folder in every case)")
    p.add_argument("--out", required=True, help="work folder: recordings (cached), explain outputs and <tag>.csv")
    p.add_argument("--seeds", type=int, default=2, help="seeds per single effect and outside case (combinations: one)")
    p.add_argument("--budget-min", type=float, default=0.0, help="start no new explain after this many minutes")
    p.add_argument("--only", default="", help="run only cases whose name contains one of these (comma-separated)")
    p.add_argument("--build-only", action="store_true", help="write the recordings, run nothing")
    p.add_argument("--csv", default="", help="also write the results table here")
    p.add_argument("--md", default="", help="also write the markdown summary here")
    a = p.parse_args()
    start, rows = time.time(), []
    env = dict(os.environ, GYROSID_QUIET="1", GYROSID_THREADS="1")
    for job in jobs(a.out, a.seeds):
        if a.only and not any(s in job["case"] for s in a.only.split(",")):
            continue
        truth = build(job)
        if a.build_only:
            print("%-40s %6d built, check %.4f sigma, base %.4f sigma" % (job["case"], job["seed"], truth["check_unabsorbed_sigma"],
                                                                          truth["base_unabsorbed_sigma"]), flush=True)
            continue
        out = os.path.join(job["dir"], a.tag)
        if not os.path.exists(os.path.join(out, "explain.json")):
            if a.budget_min and time.time() - start > 60.0 * a.budget_min:
                print("budget of %s min used: %s seed %d not run" % (a.budget_min, job["case"], job["seed"]), flush=True)
                continue
            subprocess.run([a.gyrosid, "explain", "--recording", os.path.join(job["dir"], "recording.csv"), "--seed", str(job["seed"]),
                            "--out", out], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        ex = json.load(open(os.path.join(out, "explain.json")))
        row = score(job, truth, ex, job["dir"], a.tag)
        rows.append(row)
        print("%-36s %6d %-22s %-38s %-40s right=%s %.1f s" % (job["case"], job["seed"], ex["verdict"], row["named"], row["unexplained"],
                                                              row["correct"], ex["run_time_s"]), flush=True)
    if not rows:
        return
    for path in [os.path.join(a.out, a.tag + ".csv")] + ([a.csv] if a.csv else []):
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, COLUMNS, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
    cmd = " ".join(["experiments/concealed_effects/third.py"] + sys.argv[1:])
    text = md_summary(rows, cmd, os.path.basename(a.gyrosid))
    for path in [os.path.join(a.out, a.tag + ".md")] + ([a.md] if a.md else []):
        with open(path, "w") as f:
            f.write(text)
    print(text.split("## Summary")[-1])


if __name__ == "__main__":
    main()
