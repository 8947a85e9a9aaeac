#!/usr/bin/python3
"""Importers for imucal's Ferraris sessions (github.com/mad-lab-fau/imucal, MIT; see
/work/shared/realdata/SOURCES.md), and a re-implementation of imucal's Ferraris calibration as a peer.

A Ferraris session: six static holds with one axis along gravity (x_p, x_a, y_p, y_a, z_p, z_a) and one
hand-made 360 deg turn about each axis (x_rot, y_rot, z_rot) - known angles, not known rates. The importers
write a gyrosid recording (RECORDING_FORMAT.md) that says exactly that:
  * one position_id per section, in time order; samples outside every section are left out (t_s has gaps);
  * ref_rate_{x,y,z}_dps = 0 in the static holds (Earth rate neglected, as imucal does: 0.004 deg/s against
    a 0.06 deg/s quantum) and, in a turn, the mean rate of a 360 deg turn about the section's axis (so the
    reference's integral over the section is the known angle); `# reference: angle` tells gyrosid to fit each
    turn by its integral and the holds sample by sample;
  * the turn's direction: imucal assumes -360 deg (clockwise, "the gyro shows negative values"); the
    importer takes the sign the gyro itself reports (a sign error would mean a scale factor of -1), and
    records it in the metadata;
  * temp_c = 25: neither session records a temperature (the placeholder is constant, so gyrosid fits a
    constant bias);
  * annotated_session.csv is in raw counts: gyro_dps = counts / 16.4 (the +-2000 deg/s range of a 16-bit
    MEMS gyro), accel_mps2 = counts * 9.81 / 2048 (+-16 g) - nominal scales; the calibration measures the
    true ones (imucal's K_g is in counts per deg/s, so gyrosid's K = 16.4 * |row of (I + M)|);
  * example_ferraris_session.csv is already in deg/s and m/s^2 at 102.4 Hz; its sections come from
    example_ferraris_session_list.json (start inclusive, end exclusive, as imucal's iloc[start:end]).
"""
import json
import math
import os

import numpy as np

SECTIONS = ["x_p", "x_a", "y_p", "y_a", "z_p", "z_a", "x_rot", "y_rot", "z_rot"]
NOMINAL_COUNTS_PER_DPS = 16.4
NOMINAL_COUNTS_PER_MPS2 = 2048 / 9.81


def _read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    return header, rows


def annotated_session(path):
    """imucal's annotated_session.csv -> {section: (sample index, gyro counts (n,3), accel counts (n,3))}."""
    header, rows = _read_csv(path)
    col = {n: i for i, n in enumerate(header)}
    out = {}
    for part in SECTIONS:
        sel = [r for r in rows if r[col["part"]] == part]
        idx = np.array([int(r[col["samples"]]) for r in sel])
        gyr = np.array([[float(r[col["gyr_" + a]]) for a in "xyz"] for r in sel])
        acc = np.array([[float(r[col["acc_" + a]]) for a in "xyz"] for r in sel])
        out[part] = (idx, gyr, acc)
    return out


def ferraris_session(csv_path, list_path):
    """example_ferraris_session.csv + its section list -> the same structure (deg/s, m/s^2)."""
    header, rows = _read_csv(csv_path)
    col = {n: i for i, n in enumerate(header)}
    data = np.array([[float(v) for v in r] for r in rows])
    sections = json.load(open(list_path))
    out = {}
    for part in SECTIONS:
        s, e = sections[part]["start"], sections[part]["end"]
        out[part] = (data[s:e, col["n_samples"]].astype(int), data[s:e, [col["gyr_" + a] for a in "xyz"]],
                     data[s:e, [col["acc_" + a] for a in "xyz"]])
    return out


def turn_signs(parts):
    """+1 or -1 per turn: the sign of its integral on the turning axis after the holds' mean is removed."""
    bias = np.mean(np.vstack([parts[p][1] for p in SECTIONS[:6]]), axis=0)
    return {p: float(np.sign(np.sum(parts[p][1][:, i] - bias[i]))) for i, p in enumerate(SECTIONS[6:])}


def write_recording(path, parts, rate_hz, gyro_scale, accel_scale, source):
    """The sections as a gyrosid recording (time order, gaps where no section is)."""
    signs = turn_signs(parts)
    order = sorted(SECTIONS, key=lambda p: parts[p][0][0])
    lines = []
    for pid, part in enumerate(order, start=1):
        idx, gyr, acc = parts[part]
        ref = np.zeros(3)
        if part.endswith("_rot"):
            axis = "xyz".index(part[0])
            ref[axis] = signs[part] * 360.0 / (len(idx) / rate_hz)
        for k in range(len(idx)):
            g = gyr[k] / gyro_scale
            a = acc[k] / accel_scale
            lines.append("%.10g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,25,%.17g,%.17g,%.17g,%d\n"
                         % (idx[k] / rate_hz, ref[0], ref[1], ref[2], g[0], g[1], g[2], a[0], a[1], a[2], pid))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# format: gyrosid-recording/1\n# sensor: imucal Ferraris session (%s)\n" % source)
        f.write("# sample_rate_hz: %g\n# reference: angle\n" % rate_hz)
        f.write("# description: static holds (reference 0, Earth rate neglected) and 360 deg turns known by their angle; "
                "turn signs from the gyro: %s; temp_c is a constant placeholder (not recorded)\n"
                % ", ".join("%s %+d" % (p, signs[p]) for p in SECTIONS[6:]))
        f.write("t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps,temp_c,"
                "accel_x_mps2,accel_y_mps2,accel_z_mps2,position_id\n")
        f.writelines(lines)
    os.replace(tmp, path)
    return signs


def ferraris_peer(parts, rate_hz, grav=9.81, expected_angle=-360.0):
    """Ferraris's calibration as imucal computes it (its equations re-derived, not its code):
    accelerometer K_a, R_a, b_a from the holds; gyro bias b_g = mean of all holds (Earth rate ignored);
    K_ga = (U_p - U_a) / (2 grav) per hold pair; each turn's gyro readings, less b_g and K_ga times the
    calibrated acceleration, summed / rate_hz = W_s column; (W_s / angle) = K_g R_g with K_g the row norms."""
    mean = {p: (parts[p][1].mean(axis=0), parts[p][2].mean(axis=0)) for p in SECTIONS[:6]}
    u_a_p = np.column_stack([mean[a + "_p"][1] for a in "xyz"])
    u_a_n = np.column_stack([mean[a + "_a"][1] for a in "xyz"])
    b_a = np.diag((u_a_p + u_a_n) / 2)
    u_d = u_a_p - u_a_n
    k_a = np.diag(np.sqrt(np.diag(u_d @ u_d.T)) / (2 * grav))
    r_a = np.linalg.inv(k_a) @ u_d / (2 * grav)
    b_g = np.mean(np.vstack([parts[p][1] for p in SECTIONS[:6]]), axis=0)
    k_ga = (np.column_stack([mean[a + "_p"][0] for a in "xyz"]) - np.column_stack([mean[a + "_a"][0] for a in "xyz"])) / (2 * grav)
    acc_cal = lambda acc: (np.linalg.inv(r_a) @ np.linalg.inv(k_a) @ (acc - b_a).T).T
    w_s = np.zeros((3, 3))
    for j, p in enumerate(SECTIONS[6:]):
        gyr, acc = parts[p][1], parts[p][2]
        w_s[:, j] = np.sum(gyr - (k_ga @ acc_cal(acc).T).T - b_g, axis=0) / rate_hz
    scaled = w_s / expected_angle
    k_g = np.diag(np.sqrt(np.diag(scaled @ scaled.T)))
    r_g = np.linalg.inv(k_g) @ scaled
    return {"K_a": k_a, "R_a": r_a, "b_a": b_a, "K_g": k_g, "R_g": r_g, "K_ga": k_ga, "b_g": b_g}


def triad_as_ferraris(fit, counts_per_dps):
    """gyrosid's (I + M) and bias in imucal's terms: K_i = scale * |row i|, R = rows normalised (the +360
    convention: imucal's R_g for -360 is -R), b in counts. Sigmas to first order from gyrosid's."""
    m = np.array([[np.nan if v is None else v for v in r] for r in fit["misalignment"]["matrix"]])
    s = np.array([[np.nan if v is None else v for v in r] for r in fit["misalignment"]["sigma"]])
    k = np.eye(3) + m
    norms = np.linalg.norm(k, axis=1)
    out = {"K": counts_per_dps * norms, "K_sigma": counts_per_dps * np.diag(s) * np.abs(np.diag(k)) / norms,
           "R": k / norms[:, None], "R_sigma": s / norms[:, None],
           "b": np.array(fit["bias_dph"]["value"]) / 3600.0 * counts_per_dps,
           "b_sigma": np.array(fit["bias_dph"]["sigma"]) / 3600.0 * counts_per_dps}
    return out


if __name__ == "__main__":
    import sys
    root = sys.argv[1] if len(sys.argv) > 1 else "/work/shared/realdata/imucal"
    parts = annotated_session(os.path.join(root, "example_data", "annotated_session.csv"))
    peer = ferraris_peer(parts, 204.8)
    snap = json.load(open(os.path.join(root, "tests", "snapshots", "example_cal.json")))
    for key in ("K_a", "R_a", "b_a", "K_g", "R_g", "K_ga", "b_g"):
        print(key, "max |peer - imucal snapshot| =", float(np.max(np.abs(np.array(peer[key]) - np.array(snap[key])))))
