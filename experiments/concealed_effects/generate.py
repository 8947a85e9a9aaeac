"""Recordings with one effect concealed: the base sensor simulated by gyrosid, the effect added either by
the sensor model itself (Shupe, asymmetry, thermal lag, noise) or here, from the recorded channels, by code
independent of gyrosid's physics terms (hysteresis from the probe's direction, warm-up, ageing, missing
temperature or rate orders, magnetic and g-sensitivity, a supply voltage, a bias step).

Every effect's size is set by the RMS of the part the simulation cannot absorb: the effect is projected off
the simulation's structure (bias cubic in the probe temperature, scale factor quadratic in rate and linear
in temperature) by least squares, and scaled to magnitude x noise sigma.
"""
import copy
import io
import math
import os

import numpy as np
import yaml

G = 9.80665


def read_recording(path):
    meta, lines = [], []
    with open(path) as f:
        for line in f:
            (meta if line.startswith("#") else lines).append(line)
    header = lines[0].strip().split(",")
    data = np.loadtxt(io.StringIO("".join(lines[1:])), delimiter=",", ndmin=2)
    return meta, {name: data[:, i].copy() for i, name in enumerate(header)}


def write_recording(path, meta, cols):
    names = list(cols.keys())
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.writelines(meta)
        f.write(",".join(names) + "\n")
        np.savetxt(f, np.column_stack([cols[n] for n in names]), delimiter=",", fmt="%.17g")
    os.replace(tmp, path)


def structure(cols):
    """The simulation's regressors: bias cubic in T, scale factor quadratic in rate, linear in T."""
    t = (cols["temp_c"] - 10.0) / 70.0
    w = cols["ref_rate_dps"]
    u = w / 100.0
    return np.column_stack([np.ones_like(t), t, t ** 2, t ** 3, w, w * u, w * u ** 2, w * t])


def unabsorbed(cols, shape):
    x = structure(cols)
    beta, *_ = np.linalg.lstsq(x, shape, rcond=None)
    return shape - x @ beta


def rms(v):
    return float(np.sqrt(np.mean(np.square(v))))


def thermal_branch(cols):
    """+1/2 while the sensor's temperature rises, -1/2 while it falls, held through plateaus (the hysteresis
    branch), from the sign of the recorded probe temperature's change."""
    step = np.diff(cols["temp_c"], prepend=cols["temp_c"][0])
    b = np.zeros_like(step)
    state = 0.0
    for i, s in enumerate(step):
        if s > 1e-6:
            state = 0.5
        elif s < -1e-6:
            state = -0.5
        b[i] = state
    first = np.flatnonzero(b)
    if first.size:
        b[: first[0]] = b[first[0]]
    return b


def table_angle_deg(cols):
    t, w = cols["t_s"], cols["ref_rate_dps"]
    return np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])


def add_channels(cols, seed):
    """A magnetometer on the table (the Earth's field turning with it) and a slowly wandering supply."""
    angle = np.radians(table_angle_deg(cols))
    cols["mag_x_ut"] = 20.0 * np.cos(angle) + 5.0
    rng = np.random.default_rng(seed + 7919)
    t = cols["t_s"]
    phases = rng.uniform(0, 2 * math.pi, 3)
    cols["supply_v"] = 5.0 + sum(0.1 * np.sin(2 * math.pi * t / p + ph) for p, ph in zip((1700.0, 4100.0, 9000.0), phases))


def shape_of(effect, cols, spec):
    """The effect's signal in deg/h at unit coefficient (Python-side effects)."""
    t = cols["t_s"] - cols["t_s"][0]
    temp = (cols["temp_c"] - 10.0) / 70.0
    w = cols["ref_rate_dps"]
    if effect == "temperature_bias":
        return temp ** 4
    if effect == "thermal_hysteresis":
        return thermal_branch(cols)
    if effect == "warmup_transient":
        return np.exp(-t / spec["tau_s"])
    if effect == "aging_trend":
        return t / 3600.0
    if effect == "scale_factor_nonlinearity":
        return w * (w / 100.0) ** 3 * 3600.0 * 1e-6  # 1 ppm of u^3 at full scale, in deg/h
    if effect == "scale_factor_temperature":
        return w * temp ** 2 * 3600.0 * 1e-6
    if effect == "magnetic_sensitivity":
        return cols["mag_x_ut"]
    if effect == "g_sensitivity":
        return cols["accel_z_mps2"] / G
    if effect == "g2_sensitivity":
        return (cols["accel_z_mps2"] / G) ** 2
    raise KeyError(effect)


def tilt_per_plateau(cols):
    """Replaces the specific force by one tilt per temperature plateau (tilt changes with every step)."""
    chamber = cols["chamber_temp_c"]
    # A plateau index that advances when a ramp ends.
    plateau = np.zeros_like(chamber, dtype=int)
    k, ramping = 0, False
    for i in range(1, len(chamber)):
        moving = abs(chamber[i] - chamber[i - 1]) > 1e-9
        if ramping and not moving:
            k += 1
        ramping = moving
        plateau[i] = k
    tilt = np.radians(20.0 * plateau)
    cols["accel_x_mps2"] = G * np.sin(tilt)
    cols["accel_y_mps2"] = np.zeros_like(tilt)
    cols["accel_z_mps2"] = G * np.cos(tilt)


def sensor_variant(base, out_path, shupe=None, asymmetry=None, coil_tau=None, noise=None, perturb=False):
    s = copy.deepcopy(base)
    if shupe is not None:
        s["shupe_dph_per_c_per_min"] = float(shupe)
    if asymmetry is not None:
        s["scale_factor"]["asymmetry_ppm"] = float(asymmetry)
    if coil_tau is not None:
        s["thermal"]["coil_tau_s"] = float(coil_tau)
    if noise:
        s["noise"].update(noise)
    if perturb:
        s["bias"]["constant_dph"] *= 1.2
        s["bias"]["temperature"]["coefficients_dph"] = [c * 1.3 for c in s["bias"]["temperature"]["coefficients_dph"]]
        s["scale_factor"]["rate"]["coefficients_ppm"] = [c * 1.2 for c in s["scale_factor"]["rate"]["coefficients_ppm"]]
    with open(out_path, "w") as f:
        yaml.safe_dump(s, f, sort_keys=False)
    return out_path
