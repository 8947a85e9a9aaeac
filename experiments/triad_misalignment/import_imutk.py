#!/usr/bin/python3
"""Importer for IMU-TK's Xsens session (github.com/Kyle-ak/imu_tk, a mirror of A. Pretto's IMU-TK, BSD; see
/work/shared/realdata/SOURCES.md), and a re-implementation of IMU-TK's multi-position calibration as a peer.

The session (`bin/test_data/xsens_{acc,gyro}.mat`): whitespace-separated text despite the name, columns
t [s], x, y, z in raw unsigned 16-bit counts (about 32768 at zero), 100 Hz, 511.7 s: a 50 s static start,
then the IMU turned by hand between ~37 static orientations. Nothing in it is a known rate or a known angle:
IMU-TK's reference is gravity - the accelerometer's gravity direction in one hold, carried through the gyro's
integrated rotation, must arrive at the next hold's direction (Tedaldi, Pretto, Menegatti, ICRA 2014).

What the importer writes (RECORDING_FORMAT.md), `write_recording`:
  * the static holds, one position_id each (1, 2, ...), found as IMU-TK finds them: the accelerometer's
    variance over a 101-sample window below `multiplier` times its median in the first 50 s (the static start);
  * ref_rate_{x,y,z}_dps = 0 in every hold (Earth rate neglected: 0.004 deg/s against a noise of 0.25 deg/s
    per sample);
  * turns=False: the turns between holds left out (t_s has gaps) - gyrosid then determines each gyro's bias,
    noise and g-sensitivity, and reports every entry of M as not determined (null);
  * turns=True: the turns too, position_id 0 ("in motion"; their reference column holds 0 and is not read),
    under `# reference: gravity` - gyrosid's reference=gravity (solvers/triad/gravity_turns.h) then fits M
    from them: each turn's compensated, integrated rotation must carry the gravity direction of the hold before
    it into that of the hold after it, IMU-TK's reference;
  * gyro_dps = (counts - 32768) / 6258 rad/s in deg/s (IMU-TK's own initial guess, 6258 counts per rad/s);
    accel_mps2 from the peer's accelerometer calibration (|a| = g over the holds); temp_c = 25, a constant
    placeholder (not recorded).
`imutk_peer` re-derives IMU-TK's method in numpy (scipy least squares) as the independent check.
"""
import math
import os

import numpy as np

ZERO_COUNTS = 32768.0
GYRO_COUNTS_PER_RADPS = 6258.0   # IMU-TK's test_imu_calib initial gyro scale 1/6258 rad/s per count
GRAVITY = 9.8009492468906        # IMU-TK's test_imu_calib setGravityMagnitude
WINDOW = 101                     # IMU-TK's default interval_n_samples
INIT_S = 50.0                    # IMU-TK's test_imu_calib setInitStaticIntervalDuration


def read_mat(path):
    """One IMU-TK ASCII '.mat' file -> (t_s (n,), counts (n,3))."""
    d = np.loadtxt(path, ndmin=2)
    if d.shape[1] != 4:
        raise ValueError("%s: expected 4 whitespace-separated columns (t x y z), found %d" % (path, d.shape[1]))
    return d[:, 0], d[:, 1:4]


def static_intervals(t, acc, multiplier=5.0):
    """[(begin, end)) sample ranges of the static holds: windows whose summed accelerometer variance is below
    multiplier x its median over the static start; holds shorter than one window are dropped."""
    from numpy.lib.stride_tricks import sliding_window_view
    var = sliding_window_view(acc, WINDOW, axis=0).var(axis=-1).sum(axis=1)
    n_init = int(np.sum(t < t[0] + INIT_S))
    threshold = multiplier * np.median(var[: max(1, n_init - WINDOW)])
    static = np.r_[var < threshold, np.zeros(WINDOW - 1, dtype=bool)]
    edges = np.flatnonzero(np.diff(np.r_[0, static.astype(int), 0]))
    return [(int(b), int(e)) for b, e in zip(edges[::2], edges[1::2]) if e - b >= WINDOW]


def _acc_model(p, raw):
    """IMU-TK's accelerometer model: a = T K (raw - b), T upper unit-triangular (3 angles), K diagonal."""
    t = np.array([[1.0, -p[0], p[1]], [0.0, 1.0, -p[2]], [0.0, 0.0, 1.0]])
    return (t @ np.diag(p[3:6]) @ (raw - p[6:9]).T).T


def accel_calibration(acc, intervals):
    """Fit |a| = g over the holds' means (9 parameters); returns the parameters and a -> m/s^2 function."""
    from scipy.optimize import least_squares
    means = np.array([acc[b:e].mean(axis=0) for b, e in intervals])
    scale0 = GRAVITY / np.linalg.norm(means[0] - ZERO_COUNTS)
    p0 = np.r_[0, 0, 0, scale0, scale0, scale0, ZERO_COUNTS, ZERO_COUNTS, ZERO_COUNTS]
    sol = least_squares(lambda p: GRAVITY ** 2 - np.sum(_acc_model(p, means) ** 2, axis=1), p0, x_scale="jac")
    return sol.x, lambda raw: _acc_model(sol.x, raw)


def _gyro_matrix(p):
    """IMU-TK's gyro model omega = T K (raw - b): T with unit diagonal and six small angles, K diagonal."""
    t = np.array([[1.0, -p[0], p[1]], [p[2], 1.0, -p[3]], [-p[4], p[5], 1.0]])
    return t @ np.diag(p[6:9])


def _rotation(omega, dt):
    """Product of the per-sample rotations exp([omega_k dt]x) (body k -> body k+1), by pairwise reduction."""
    theta = omega * dt
    angle = np.linalg.norm(theta, axis=1)
    axis = theta / np.where(angle > 0, angle, 1.0)[:, None]
    k = np.zeros((len(theta), 3, 3))
    k[:, 0, 1], k[:, 0, 2], k[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    k[:, 1, 0], k[:, 2, 0], k[:, 2, 1] = axis[:, 2], -axis[:, 1], axis[:, 0]
    s, c = np.sin(angle)[:, None, None], (1 - np.cos(angle))[:, None, None]
    r = np.eye(3) + s * k + c * (k @ k)
    while len(r) > 1:
        if len(r) % 2:
            r = np.concatenate([r, np.eye(3)[None]])
        r = r[0::2] @ r[1::2]
    return r[0]


def imutk_peer(t, gyro, acc, intervals):
    """IMU-TK's multi-position calibration, its equations re-derived (not its code): gyro bias = mean of the
    static start; accelerometer from |a| = g; then the gyro's T K minimising, over every turn between two
    holds, |u_next - R^T u_prev| with u a hold's unit gravity direction and R the turn integrated from the
    calibrated gyro. Returns (I + M) in gyrosid's terms ((T K 6258)^-1 for gyro_dps = counts / 6258 rad/s),
    its sigma (Gauss-Newton covariance scaled by the residual variance), the bias in counts and the fit."""
    from scipy.optimize import least_squares
    _, acc_cal = accel_calibration(acc, intervals)
    u = [acc_cal(acc[b:e]).mean(axis=0) for b, e in intervals]
    u = [v / np.linalg.norm(v) for v in u]
    b0, e0 = intervals[0]
    bias = gyro[b0:e0].mean(axis=0)
    turns = [(intervals[k][1], intervals[k + 1][0]) for k in range(len(intervals) - 1)]
    dt = float(np.median(np.diff(t)))

    def residual(p):
        a = _gyro_matrix(p)
        out = []
        for k, (b, e) in enumerate(turns):
            r = _rotation((a @ (gyro[b:e] - bias).T).T, dt)
            out.append(u[k + 1] - r.T @ u[k])
        return np.concatenate(out)

    p0 = np.r_[np.zeros(6), np.full(3, 1.0 / GYRO_COUNTS_PER_RADPS)]
    sol = least_squares(residual, p0, x_scale=np.r_[np.full(6, 1e-3), np.full(3, 1e-6)])
    n, m = len(sol.fun), len(sol.x)
    cov = np.linalg.pinv(sol.jac.T @ sol.jac) * float(sol.fun @ sol.fun) / (n - m)
    ipm = lambda p: np.linalg.inv(_gyro_matrix(p) * GYRO_COUNTS_PER_RADPS)
    # sigma of I + M by first-order propagation (central differences of the map p -> (T K 6258)^-1).
    jac = np.zeros((9, m))
    for i in range(m):
        h = 1e-6 * max(abs(sol.x[i]), 1e-3 if i < 6 else 1e-6)
        dp = np.zeros(m)
        dp[i] = h
        jac[:, i] = ((ipm(sol.x + dp) - ipm(sol.x - dp)) / (2 * h)).ravel()
    sigma = np.sqrt(np.diag(jac @ cov @ jac.T)).reshape(3, 3)
    return {"I_plus_M": ipm(sol.x), "sigma": sigma, "bias_counts": bias, "turns": len(turns),
            "residual_rms": float(np.sqrt(np.mean(sol.fun ** 2))), "params": sol.x}


def write_recording(path, t, gyro, acc_mps2, intervals, source, turns=False):
    """The static holds as a gyrosid recording (position_id per hold, reference 0), atomically. turns=True also
    writes the hand turns between them, position_id 0 (in motion; their reference column, 0, is not read) under
    `# reference: gravity`, the layout of gyrosid's reference=gravity (solvers/triad/gravity_turns.h)."""
    gyro_dps = np.degrees((gyro - ZERO_COUNTS) / GYRO_COUNTS_PER_RADPS)
    pid = np.full(len(t), -1)
    for k, (b, e) in enumerate(intervals, start=1):
        pid[b:e] = k
    if turns:
        pid[intervals[0][0]:intervals[-1][1]][pid[intervals[0][0]:intervals[-1][1]] < 0] = 0
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sensor: Xsens IMU, IMU-TK test data (%s)\n# sample_rate_hz: %g\n"
                % (source, round(1.0 / float(np.median(np.diff(t))), 3)))
        if turns:
            f.write("# reference: gravity\n")
        f.write("# description: %d static holds found by the accelerometer variance (IMU-TK's detector); reference 0 "
                "(Earth rate neglected); %s; gyro = (counts - 32768) / 6258 rad/s; temp_c is a constant placeholder (not recorded)\n"
                % (len(intervals), "the hand turns between holds with position_id 0 (known by the holds' gravity directions)" if turns else
                   "the hand turns between holds are left out (gravity-referenced, no known rate or angle)"))
        f.write("t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps,temp_c,"
                "accel_x_mps2,accel_y_mps2,accel_z_mps2,position_id\n")
        for k in np.flatnonzero(pid >= 0):
            g, a = gyro_dps[k], acc_mps2[k]
            f.write("%.10g,0,0,0,%.17g,%.17g,%.17g,25,%.17g,%.17g,%.17g,%d\n" % (t[k], g[0], g[1], g[2], a[0], a[1], a[2], pid[k]))
    os.replace(tmp, path)


def load_session(root):
    """(t, gyro counts, acc counts, static intervals) of the Xsens session under root (imu_tk/)."""
    d = os.path.join(root, "bin", "test_data")
    t, acc = read_mat(os.path.join(d, "xsens_acc.mat"))
    tg, gyro = read_mat(os.path.join(d, "xsens_gyro.mat"))
    if len(t) != len(tg) or np.max(np.abs(t - tg)) > 1e-9:
        raise ValueError("%s: xsens_acc.mat and xsens_gyro.mat do not share their time stamps" % d)
    return t, gyro, acc, static_intervals(t, acc)


def synthetic_check(seed=1, holds=30, noise_counts=3.0):
    """The peer on a synthetic session (synthetic_session). Returns (planted I + M, estimated I + M, sigma)."""
    t, gyro, acc, planted = synthetic_session(seed, holds, noise_counts)
    peer = imutk_peer(t, gyro, acc, static_intervals(t, acc))
    return planted, peer["I_plus_M"], peer["sigma"]


def synthetic_session(seed=1, holds=30, noise_counts=3.0):
    """A synthetic session with planted T K (gyro) and accelerometer parameters: holds of 3 s at successive
    orientations, turns of 2 s about a fixed random axis with a sine-shaped rate (so each turn's rotation is
    exactly exp(angle [axis]x), independent of any integration). Returns (t, gyro counts, acc counts, planted
    I + M in gyrosid's terms)."""
    rng = np.random.default_rng(seed)
    rate, n_hold, n_turn = 100.0, 300, 200
    p_gyro = np.r_[rng.normal(0, 3e-3, 6), (1.0 + rng.normal(0, 0.02, 3)) / GYRO_COUNTS_PER_RADPS]
    a_gyro = _gyro_matrix(p_gyro)
    p_acc = np.r_[rng.normal(0, 2e-3, 3), (1.0 + rng.normal(0, 0.02, 3)) * GRAVITY / 3500.0, ZERO_COUNTS + rng.normal(0, 50, 3)]
    a_acc = np.array([[1.0, -p_acc[0], p_acc[1]], [0.0, 1.0, -p_acc[2]], [0.0, 0.0, 1.0]]) @ np.diag(p_acc[3:6])
    b_gyro = ZERO_COUNTS + rng.normal(0, 100, 3)
    u = np.array([0.0, 0.0, 1.0])
    omega, gravity = [], []
    shape = np.sin(np.pi * (np.arange(n_turn) + 0.5) / n_turn)
    for k in range(holds):
        omega.append(np.zeros((n_hold if k else 5000, 3)))
        gravity.append(np.tile(u, (len(omega[-1]), 1)))
        if k == holds - 1:
            break
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = rng.uniform(np.pi / 3, np.pi)
        w = np.outer(shape / shape.sum() * angle * rate, axis)
        omega.append(w)
        gravity.append(np.tile(u, (n_turn, 1)))  # not static: excluded by the detector's window
        kx = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        r = np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx
        u = r.T @ u
    omega, gravity = np.vstack(omega), np.vstack(gravity)
    t = np.arange(len(omega)) / rate
    gyro = np.linalg.solve(a_gyro, omega.T).T + b_gyro + rng.normal(0, noise_counts, omega.shape)
    acc = np.linalg.solve(a_acc, GRAVITY * gravity.T).T + p_acc[6:9] + rng.normal(0, noise_counts, omega.shape)
    moving = np.linalg.norm(omega, axis=1) > 0  # the turns also shake the accelerometer
    acc[moving] += rng.normal(0, 200, (int(moving.sum()), 3))
    return t, gyro, acc, np.linalg.inv(a_gyro * GYRO_COUNTS_PER_RADPS)


if __name__ == "__main__":
    import sys
    t, gyro, acc, iv = load_session(sys.argv[1] if len(sys.argv) > 1 else "/work/shared/realdata/imu_tk")
    peer = imutk_peer(t, gyro, acc, iv)
    np.set_printoptions(precision=6, suppress=True)
    print(len(iv), "holds,", peer["turns"], "turns, residual rms", peer["residual_rms"])
    print("I + M:\n", peer["I_plus_M"], "\nsigma:\n", peer["sigma"])
    print("bias counts", peer["bias_counts"], "deg/h", np.degrees((peer["bias_counts"] - ZERO_COUNTS) / GYRO_COUNTS_PER_RADPS) * 3600)
