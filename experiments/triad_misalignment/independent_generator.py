#!/usr/bin/python3
"""An independent triad generator: gyrosid's triad fit checked on data made under other assumptions.

Nothing here comes from gyrosid's simulator. Its own conventions:
  * the planted matrix is K = diag(1 + s) (I + L) R: scale factors s, a strictly lower-triangular
    non-orthogonality L and a small rotation R = exp([r]x) (Rodrigues) - not thesis angles;
  * a MEMS-like sensor: 100 Hz, white noise of N deg/s/sqrt(Hz) (not deg/h at 1 Hz), a bias linear in a
    drifting temperature, gyro samples are instantaneous rates (not interval means), optionally a scale
    factor falling with the square of the gyro's own input rate (--cubic-ppm-per-dps2);
  * its own motion programme: the body's attitude C_nb is propagated in closed form for rotations about a
    body-fixed axis (axes +-x, +-y, +-z at 20 and 45 deg/s, and the diagonals (1,1,0), (1,0,1), (0,1,1),
    (1,1,1) - multi-axis turns), with static holds between them in orientations reached by those turns;
    Earth rate at 52 deg N enters through C_nb; specific force is gravity in body axes.
It writes a recording in the format of RECORDING_FORMAT.md, and computes the Cramer-Rao bound of K with
its own design matrix. Two peers run on the same data: numpy's least squares on the same linear model,
and the textbook rate-table estimator M_ij = (g_i(+w_j) - g_i(-w_j)) / (2 w) from opposite turns.

    independent_generator.py --seed 7 --out triad.csv --truth truth.json
"""
import argparse
import json
import math
import os

import numpy as np

EARTH_RATE = 7.2921151467e-5  # rad/s
LATITUDE = math.radians(52.0)
GRAVITY = 9.8127
RATE_HZ = 100.0


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def rodrigues(r):
    t = np.linalg.norm(r)
    if t < 1e-15:
        return np.eye(3)
    k = skew(r / t)
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k


def planted(rng, cubic_ppm_per_dps2=0.0):
    s = rng.normal(0, 2e-3, 3)
    lower = np.tril(rng.normal(0, 1e-3, (3, 3)), -1)
    k = np.diag(1 + s) @ (np.eye(3) + lower) @ rodrigues(rng.normal(0, 2e-3, 3))
    return {"K": k, "bias_dps": rng.normal(0, 0.05, 3), "bias_temp_dps_per_c": rng.normal(0, 2e-3, 3),
            "noise_dps_rt_hz": 0.004, "cubic": cubic_ppm_per_dps2 * 1e-6 / math.radians(1.0) ** 2}


def programme():
    """(axis in body, rate deg/s, seconds) segments; rate 0 = static hold."""
    segs = [(np.array([0, 0, 1.0]), 0.0, 60)]
    axes = [np.eye(3)[i] * sgn for i in range(3) for sgn in (1, -1)]
    diag = [np.array(v, float) / np.linalg.norm(v) for v in ((1, 1, 0), (1, 0, 1), (0, 1, 1), (1, 1, 1))]
    for rate, turns in ((20.0, 1), (45.0, 2)):
        for a in axes:
            segs.append((a, rate, 360.0 * turns / rate))
            segs.append((a, 0.0, 20))
    for a in diag:
        for sgn in (1, -1):
            segs.append((sgn * a, 30.0, 360.0 / 30.0 * 1.5))  # 1.5 turns: the hold after it is a new attitude
            segs.append((a, 0.0, 20))
    return segs


def generate(seed, cubic_ppm_per_dps2=0.0):
    rng = np.random.default_rng(seed)
    p = planted(rng, cubic_ppm_per_dps2)
    c_nb = np.eye(3)  # body = NED at the start
    w_ie_n = EARTH_RATE * np.array([math.cos(LATITUDE), 0.0, -math.sin(LATITUDE)])
    dt = 1.0 / RATE_HZ
    t, ref, gyro, acc, temp = [], [], [], [], []
    t_now = 0.0
    total = sum(s[2] for s in programme())
    for axis, rate_dps, seconds in programme():
        n = int(round(seconds * RATE_HZ))
        w_rot = math.radians(rate_dps) * axis
        step = rodrigues(w_rot * dt)  # body-fixed axis: C_nb(t + dt) = C_nb(t) exp([w dt]x)
        for _ in range(n):
            w_ib_b = c_nb.T @ w_ie_n + w_rot
            temperature = 20.0 + 6.0 * t_now / total
            bias = np.radians(p["bias_dps"] + p["bias_temp_dps_per_c"] * (temperature - 20.0))
            noise = np.radians(p["noise_dps_rt_hz"]) * math.sqrt(RATE_HZ) * rng.standard_normal(3)
            t.append(t_now)
            ref.append(w_ib_b)
            w_in = p["K"] @ w_ib_b
            gyro.append(w_in * (1 + p["cubic"] * w_in ** 2) + bias + noise)  # scale factor falling with rate^2
            acc.append(c_nb.T @ np.array([0.0, 0.0, -GRAVITY]))
            temp.append(temperature)
            c_nb = c_nb @ step
            t_now += dt
    return p, np.array(t), np.array(ref), np.array(gyro), np.array(acc), np.array(temp)


def write(path, seed, t, ref, gyro, acc, temp):
    cols = {"t_s": t}
    for i, a in enumerate("xyz"):
        cols["ref_rate_%s_dps" % a] = np.degrees(ref[:, i])
    for i, a in enumerate("xyz"):
        cols["gyro_%s_dps" % a] = np.degrees(gyro[:, i])
    cols["temp_c"] = temp
    for i, a in enumerate("xyz"):
        cols["accel_%s_mps2" % a] = acc[:, i]
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sensor: independent MEMS-like triad (independent_generator.py)\n")
        f.write("# sample_rate_hz: %g\n# latitude_deg: 52\n# seed: %d\n" % (RATE_HZ, seed))
        f.write(",".join(cols) + "\n")
        np.savetxt(f, np.column_stack(list(cols.values())), delimiter=",", fmt="%.17g")
    os.replace(tmp, path)


def peers_and_bound(p, t, ref, gyro, temp):
    """Per gyro i: numpy lstsq of g_i on [omega, 1, T - 20]; the Cramer-Rao sigma of M_i. from the true noise;
    the rate-table estimator from opposite single-axis turns."""
    sigma = math.radians(p["noise_dps_rt_hz"]) * math.sqrt(RATE_HZ)
    a = np.column_stack([ref, np.ones(len(t)), temp - 20.0])
    m_ls, crb = np.zeros((3, 3)), np.zeros((3, 3))
    cov = sigma ** 2 * np.linalg.inv(a.T @ a)
    for i in range(3):
        theta, *_ = np.linalg.lstsq(a, gyro[:, i] - ref[:, i], rcond=None)
        m_ls[i] = theta[:3]
        crb[i] = np.sqrt(np.diag(cov)[:3])
    m_table = np.full((3, 3), np.nan)
    w = np.linalg.norm(ref, axis=1)
    for j in range(3):
        plus = (ref[:, j] > 0.9 * w) & (w > math.radians(15))
        minus = (ref[:, j] < -0.9 * w) & (w > math.radians(15))
        wp, wm = ref[plus, j].mean(), ref[minus, j].mean()
        for i in range(3):
            m_table[i, j] = (gyro[plus, i].mean() - gyro[minus, i].mean()) / (wp - wm) - (1.0 if i == j else 0.0)
    return m_ls, crb, m_table


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--truth", required=True)
    ap.add_argument("--cubic-ppm-per-dps2", type=float, default=0.0,
                    help="scale-factor error c w^2 of every gyro (a rate-nonlinear surface), ppm per (deg/s)^2")
    args = ap.parse_args()
    p, t, ref, gyro, acc, temp = generate(args.seed, args.cubic_ppm_per_dps2)
    write(args.out, args.seed, t, ref, gyro, acc, temp)
    m_ls, crb, m_table = peers_and_bound(p, t, ref, gyro, temp)
    truth = {"M": (p["K"] - np.eye(3)).tolist(), "bias_dph": (np.array(p["bias_dps"]) * 3600).tolist(),
             "bias_temp_dph_per_c": (np.array(p["bias_temp_dps_per_c"]) * 3600).tolist(), "bias_reference_c": 20.0,
             "crb": crb.tolist(), "numpy_lstsq": m_ls.tolist(), "rate_table": m_table.tolist()}
    tmp = args.truth + ".tmp"
    with open(tmp, "w") as f:
        json.dump(truth, f, indent=1)
    os.replace(tmp, args.truth)


if __name__ == "__main__":
    main()
