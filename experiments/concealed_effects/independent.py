"""The second, independent generator of the concealed-effects experiment: recordings written here from first
principles, without gyrosid's simulator, sensor model or physics terms, so that `gyrosid explain` is also
judged on data it did not make under its own assumptions.

It differs from the project's simulator in every part:

* sensor - an interferometric FOG whose bias is a cubic in the coil temperature about 25 C and whose
  scale-factor error is a low-order polynomial in (T, rate) given in ppm (laws gyrosid's baseline family can
  still represent), white noise 10 deg/h per 1-Hz sample plus a slow Gauss-Markov wander (0.5 deg/h, 20 min)
  and a temperature probe read to 0.01 C;
* thermal programme - 7.7 h (under the 8 h of the speed target), ramps at three rates (0.5, 1 and 2 C/min here, chosen per seed) with long
  plateaus, the probe 2 min behind the chamber (exact exponential discretisation, not gyrosid's lag);
* rate programme - blocks of a sine with slowly varying amplitude, a staircase of held rates (steps) and a
  plain sine, cycling through the record;
* each effect in its own law: Shupe on the coil's temperature rate; a coil lagging the probe through a
  discrete first-order filter; hysteresis as a play operator (the offset moves between the branches over a
  few degrees after each reversal, not at a rate threshold); a two-exponential warm-up; linear ageing; an
  exponential bias rise at the hot end; scale-factor asymmetry as separate scale factors per sense; a bias
  step (a mode hop) and a bias ramp starting mid-run (outside the library); a supply-voltage sensitivity.

An effect's size is set as in the first generator: the RMS of the part the simulation cannot absorb - here
the baseline family explain fits when no simulation is given (bias cubic in T, scale factor as a bicubic
spline surface on the thesis's grid narrowed to the data) - in units of the white noise sigma.
"""
import math

import numpy as np
from scipy.interpolate import CubicSpline

G = 9.80665
SIGMA_DPH = 10.0          # white noise per 1-Hz sample
GM_SIGMA_DPH, GM_TAU_S = 0.5, 1200.0
PROBE_TAU_S = 120.0       # probe behind the chamber
PROBE_LSB_C = 0.01

# Chamber programmes: (target C, ramp rate C/min, hold min) segments after a 30-min start plateau at 20 C.
PROGRAMMES = {
    "three_rates": [(60, 0.5, 35), (-20, 1.0, 35), (40, 2.0, 30), (0, 0.5, 30), (20, 2.0, 20)],
    "cycles": [(50, 2.0, 30), (-10, 1.0, 30), (50, 0.5, 40), (-10, 2.0, 30), (20, 1.0, 30)],
    "wide": [(70, 1.0, 60), (-30, 2.0, 60), (30, 0.5, 45), (10, 1.0, 30)],
}
# Programmes a case names itself (never drawn by seed): reversals of 2-12 C inside the range, so a loop's inner
# shape (minor loops), not only its saturated branches, is in the data.
CASE_PROGRAMMES = {
    "minor_loops": [(50, 1.0, 20), (44, 1.0, 10), (48, 1.0, 10), (40, 1.0, 10), (46, 1.0, 10), (34, 1.0, 10), (42, 1.0, 10),
                    (-10, 2.0, 20), (-4, 1.0, 10), (-8, 1.0, 10), (0, 1.0, 10), (-6, 1.0, 10), (6, 1.0, 10), (0, 1.0, 10),
                    (20, 1.0, 10)],
}


def chamber_programme(name, dt=1.0):
    """Piecewise-linear chamber temperature along a programme, sampled every dt."""
    knots_t, knots_v = [0.0, 1800.0], [20.0, 20.0]
    for target, rate, hold in {**PROGRAMMES, **CASE_PROGRAMMES}[name]:
        ramp = abs(target - knots_v[-1]) / rate * 60.0
        knots_t += [knots_t[-1] + ramp, knots_t[-1] + ramp + hold * 60.0]
        knots_v += [target, target]
    t = np.arange(0.0, knots_t[-1], dt)
    return t, np.interp(t, knots_t, knots_v)


def first_order(x, tau, dt):
    """x through dy/dt = (x - y)/tau, exact for x held over each interval, starting in equilibrium."""
    if tau <= 0:
        return x.copy()
    a = math.exp(-dt / tau)
    y = np.empty_like(x)
    y[0] = x[0]
    for i in range(1, len(x)):
        y[i] = a * y[i - 1] + (1 - a) * x[i]
    return y


def rate_programme(t):
    """Blocks of 20 min cycling: an amplitude-modulated sine, a staircase of held rates, a plain sine (deg/s)."""
    block = (t // 1200).astype(int) % 3
    am = (60 + 40 * np.sin(2 * math.pi * t / 5400.0)) * np.sin(2 * math.pi * t / 97.0)
    stairs = np.array([10, -30, 60, -90, 30, -10, 90, -60])[((t % 1200) // 150).astype(int)]
    sine = 100 * np.sin(2 * math.pi * t / 233.0)
    return np.where(block == 0, am, np.where(block == 1, stairs, sine)).astype(float)


def gauss_markov(n, sigma, tau, dt, rng):
    a = math.exp(-dt / tau)
    w = rng.normal(0, sigma * math.sqrt(1 - a * a), n)
    x = np.empty(n)
    x[0] = rng.normal(0, sigma)
    for i in range(1, n):
        x[i] = a * x[i - 1] + w[i]
    return x


class Sensor:
    """The base FOG: bias cubic in the coil temperature, scale-factor error in ppm."""
    bias = (8.0, 0.35, -0.004, 5e-5)               # deg/h, per C, per C^2, per C^3 about 25 C
    sf = {"s0": 150.0, "sT": 4.0, "sT2": -0.03, "su": 25.0, "su2": -40.0, "sTu": 0.5}  # ppm; u = rate / 100 deg/s

    def bias_dph(self, coil):
        d = coil - 25.0
        b0, b1, b2, b3 = self.bias
        return b0 + b1 * d + b2 * d ** 2 + b3 * d ** 3

    def sf_ppm(self, coil, w):
        d, u, s = coil - 25.0, w / 100.0, self.sf
        return s["s0"] + s["sT"] * d + s["sT2"] * d ** 2 + s["su"] * u + s["su2"] * u ** 2 + s["sTu"] * d * u


def play_operator(x, r):
    """The play (backlash) hysteresis operator of half-width r: y follows x once x is more than r away."""
    y = np.empty_like(x)
    y[0] = x[0]
    for i in range(1, len(x)):
        y[i] = min(max(y[i - 1], x[i] - r), x[i] + r)
    return y


# Effect shapes at unit size (deg/h unless stated): each a function of the sample arrays.
def shape(effect, s, spec):
    t, coil, w = s["t"], s["coil"], s["w"]
    if effect == "shupe":                       # per (C/min) of the coil's temperature rate
        return np.gradient(coil, t) * 60.0
    if effect == "thermal_hysteresis":          # heating-branch bias minus cooling-branch bias = 1
        # One play of half-width play_c, or a weighted sum of plays (a Prandtl-Ishlinskii loop; weights sum to 1).
        widths = np.atleast_1d(spec.get("play_c", 1.5)).astype(float)
        weights = np.atleast_1d(spec.get("play_weights", np.full(len(widths), 1.0 / len(widths)))).astype(float)
        return sum(wk * 0.5 * (coil - play_operator(coil, r)) / r for r, wk in zip(widths, weights))
    if effect == "scale_factor_asymmetry":      # 1 ppm of scale factor difference between the senses
        # A step at zero rate (sign), or a smooth transition over +-transition_dps (tanh).
        r = spec.get("transition_dps", 0.0)
        return 0.5 * (np.tanh(w / r) if r > 0 else np.sign(w)) * w * 3600.0 * 1e-6
    if effect == "temperature_bias":            # the source's hot-end rise
        return np.exp((coil - 60.0) / 8.0)
    if effect == "warmup_transient":
        return 0.6 * np.exp(-t / 600.0) + 0.4 * np.exp(-t / 2400.0)
    if effect == "aging_trend":                 # per hour
        return t / 3600.0
    if effect == "bias_step":                   # a mode hop at t_step
        return (t >= spec["t_step_s"]).astype(float)
    if effect == "bias_ramp":                   # a drift starting at t_step, per hour
        return np.maximum(t - spec["t_step_s"], 0.0) / 3600.0
    if effect == "supply_voltage":              # per volt
        return s["supply_v"] - 5.0
    raise KeyError(effect)


def spline_basis(x, knots):
    """Cardinal not-a-knot cubic splines through the knots at x, held at the ends (len(x) x len(knots))."""
    xc = np.clip(x, knots[0], knots[-1])
    out = np.empty((len(x), len(knots)))
    for j in range(len(knots)):
        e = np.zeros(len(knots))
        e[j] = 1.0
        if len(knots) == 2:
            out[:, j] = np.interp(xc, knots, e)
        else:
            out[:, j] = CubicSpline(knots, e, bc_type="not-a-knot")(xc)
    return out


def grid_within(nodes, lo, hi, gap):
    return [lo] + [x for x in nodes if lo + gap < x < hi - gap] + [hi]


def baseline_columns(temp, w_dps):
    """The baseline family explain fits without a simulation: bias cubic in T; scale factor as a bicubic
    spline surface over the thesis's grid narrowed to the data (a cubic polynomial when the ranges are
    small). Written from the description in explain's help, not from its code."""
    tl, th, wl, wh = temp.min(), temp.max(), w_dps.min(), w_dps.max()
    d = (temp - 0.5 * (tl + th)) / max(1.0, 0.5 * (th - tl))
    cols = [np.ones_like(temp), d, d ** 2, d ** 3]
    if wh - wl >= 40 and th - tl >= 10:
        tk = grid_within([-60, -20, 0, 20, 25, 40, 60, 80], tl, th, 2.0)
        wk = grid_within([-100, -80, -60, -40, -20, -10, 10, 20, 40, 60, 80, 100], wl, wh, 2.0)
        bt, bw = spline_basis(temp, tk), spline_basis(w_dps, wk)
        cols += [w_dps * bt[:, i] * bw[:, j] for i in range(len(tk)) for j in range(len(wk))]
    else:
        u = w_dps / max(abs(wl), abs(wh))
        cols += [w_dps * d ** i * u ** j for i in range(4) for j in range(4)]
    return np.column_stack(cols)


def unabsorbed(x, v):
    beta, *_ = np.linalg.lstsq(x, v, rcond=None)
    return v - x @ beta


def rms(v):
    return float(np.sqrt(np.mean(np.square(v))))


def base_signals(seed, programme):
    """Time, chamber, true probe and coil temperatures, rate and a supply voltage for one recording."""
    t, chamber = chamber_programme(programme)
    probe = first_order(chamber, PROBE_TAU_S, 1.0)
    rng = np.random.default_rng(seed + 77)
    ph = rng.uniform(0, 2 * math.pi, 3)
    supply = 5.0 + sum(0.08 * np.sin(2 * math.pi * t / p + q) for p, q in zip((1900.0, 4700.0, 11000.0), ph))
    return {"t": t, "chamber": chamber, "probe": probe, "coil": probe.copy(), "w": rate_programme(t), "supply_v": supply}


def make_recording(case, seed, sensor=None):
    """One recording: {'cols': recording columns, 'truth': what was planted, 'noise_dph': the noise}.

    case: {"effects": [{"id", "magnitude", ...}], "outside": {...}, "noise": {...}, "programme": name,
           "coil_tau_s": lag, "rate_scale": factor on the rate programme}
    """
    sensor = sensor or Sensor()
    rng = np.random.default_rng(seed)
    programme = case.get("programme") or sorted(PROGRAMMES)[seed % len(PROGRAMMES)]
    s = base_signals(seed, programme)
    s["w"] = s["w"] * case.get("rate_scale", 1.0)  # below 0.2 the rates span < 40 deg/s: a polynomial baseline
    t, n = s["t"], len(s["t"])
    truth = {"programme": programme, "effects": [], "outside": []}
    # The coil lags the probe (a planted thermal lag); every temperature law then reads the coil.
    lag = case.get("coil_tau_s", 0.0)
    s["coil"] = first_order(s["probe"], lag, 1.0) if lag else s["probe"]
    x_base = baseline_columns(quantized(s["probe"]), s["w"])
    error = sensor.bias_dph(s["coil"]) + sensor.sf_ppm(s["coil"], s["w"]) * 1e-6 * s["w"] * 3600.0
    if lag:
        lag_signal = error - (sensor.bias_dph(s["probe"]) + sensor.sf_ppm(s["probe"], s["w"]) * 1e-6 * s["w"] * 3600.0)
        truth["effects"].append({"id": "thermal_lag", "value": lag, "parameter": "tau_s",
                                 "magnitude": rms(unabsorbed(x_base, lag_signal)) / SIGMA_DPH})
    planted = np.zeros(n)
    for e in case.get("effects", []):
        spec = dict(e)
        if e["id"] in ("bias_step", "bias_ramp"):
            at = rng.uniform(0.3, 0.7)  # drawn even when the case states "at" (onsets.py): the later draws stay the same
            spec["t_step_s"] = t[0] + e.get("at", at) * (t[-1] - t[0])
        v = shape(e["id"], s, spec)
        # The size is the RMS of the part the baseline cannot absorb, or (size "raw") of the effect less its mean.
        c = e["magnitude"] * SIGMA_DPH / (rms(v - v.mean()) if e.get("size") == "raw" else rms(unabsorbed(x_base, v)))
        planted += c * v
        record = {"id": e["id"], "magnitude": e["magnitude"], "value": c,
                  "unabsorbed_sigma": rms(unabsorbed(x_base, c * v)) / SIGMA_DPH}
        if "t_step_s" in spec:
            record["t_step_s"] = spec["t_step_s"]
        (truth["outside"] if e["id"] in ("bias_step", "bias_ramp", "supply_voltage") else truth["effects"]).append(record)
    noise = rng.normal(0, SIGMA_DPH, n) + gauss_markov(n, GM_SIGMA_DPH, GM_TAU_S, 1.0, rng)
    extra = case.get("noise", {})
    if "gauss_markov" in extra:
        noise += gauss_markov(n, extra["gauss_markov"]["sigma_dph"], extra["gauss_markov"]["tau_s"], 1.0, rng)
    if "rrw_dph_rt_h" in extra:
        noise += np.cumsum(rng.normal(0, extra["rrw_dph_rt_h"] / 60.0, n))  # per-sample increments of a K deg/h/rt(h) walk
    gyro = s["w"] + (error + planted + noise) / 3600.0
    cols = {"t_s": t, "ref_rate_dps": s["w"], "temp_c": quantized(s["probe"]), "gyro_dps": gyro,
            "chamber_temp_c": np.round(s["chamber"], 2), "supply_v": np.round(s["supply_v"], 4)}
    truth["planted_unabsorbed_dph"] = unabsorbed(x_base, planted + (lag_signal if lag else 0.0))
    return {"cols": cols, "truth": truth, "noise_dph": noise}


def quantized(probe):
    return np.round(probe / PROBE_LSB_C) * PROBE_LSB_C
