"""A GMWM-class reference fit in numpy/scipy (Guerrier, Skaloud, Stebler & Victoria-Feser, IEEE TAES 2013),
written for this comparison and independent of gyrosid's estimator.

Moments: the Haar MODWT wavelet variance nu_j^2 at dyadic scales tau_j = 2^(j-1) dt (computed from block
means, = half the overlapping Allan variance). Weight: diagonal, the inverse of each estimate's variance by
Percival & Walden's chi-square approximation with eta3 = max(M_j / 2^j, 1) degrees of freedom,
var(nu_j^2) = 2 nu_j^4 / eta3 (the usual GMWM choice for a quick fit). Estimate: argmin of
sum_j (nu_j^2 - nu_j^2(theta))^2 / var_j over the log-parameters, L-BFGS-B from many starts.
"""
import numpy as np
from scipy.optimize import minimize

LN2PI = 2.0 * np.log(2.0) / np.pi


def wavelet_variance(y, dt, max_scale_fraction=0.1):
    """(tau_s, nu2, eta3): Haar MODWT wavelet variance at tau_j = 2^(j-1) dt up to a fraction of the record."""
    c = np.concatenate([[0.0], np.cumsum(y - y.mean())])
    n = len(y)
    taus, nu2, eta = [], [], []
    half = 1
    while half * 2 <= max_scale_fraction * n * 2 and 2 * half < n:
        # W_t = (mean of y[t-2h+1 .. t-h] - mean of y[t-h+1 .. t]) / 2, t from 2h-1 (boundary coefficients dropped)
        s_late = c[2 * half:] - c[half:-half]
        s_early = c[half:-half] - c[:-2 * half]
        w = (s_early - s_late) / (2.0 * half)
        m = len(w)
        taus.append(half * dt)
        nu2.append(np.mean(w * w))
        eta.append(max(m / (2.0 * half), 1.0))
        half *= 2
    return np.array(taus), np.array(nu2), np.array(eta)


def model_wv(theta, taus, structure):
    """Wavelet variance (= Allan variance / 2) of the structure's terms at taus; theta in natural units."""
    av = np.zeros_like(taus)
    k = 0
    for term in structure:
        if term == "Q":
            av += 3.0 * theta[k] ** 2 / taus ** 2; k += 1
        elif term == "N":
            av += theta[k] ** 2 / taus; k += 1
        elif term == "B":
            av += LN2PI * theta[k] ** 2; k += 1
        elif term == "K":
            av += theta[k] ** 2 * taus / 3.0; k += 1
        elif term == "GM":
            s, T = theta[k], theta[k + 1]; k += 2
            r = taus / T
            av += 2 * s * s * T / taus * (1 - (3 - 4 * np.exp(-r) + np.exp(-2 * r)) / (2 * r))
    return av / 2.0


def unpack(x, structure):
    """log-parameters -> natural (Gauss-Markov times sorted ascending so the labels are stable)."""
    theta = list(np.exp(x))
    k, gms = 0, []
    for term in structure:
        if term == "GM":
            gms.append((k, theta[k], theta[k + 1])); k += 2
        else:
            k += 1
    order = sorted(gms, key=lambda g: g[2])
    for (k0, _, _), (_, s, T) in zip(gms, order):
        theta[k0], theta[k0 + 1] = s, T
    return np.array(theta)


def fit(y, dt, structure, seed=0, starts=24):
    taus, nu2, eta = wavelet_variance(y, dt)
    w = eta / (2.0 * nu2 ** 2)
    t_lo, t_hi = np.log(2 * dt), np.log(len(y) * dt)

    def objective(x):
        r = nu2 - model_wv(unpack(x, structure), taus, structure)
        return np.sum(w * r * r)

    rng = np.random.default_rng(seed)
    level = np.log(np.sqrt(2 * np.median(nu2 * taus)))  # a scale for the starting variances
    best = None
    for s in range(starts):
        x0 = []
        gm = 0
        for term in structure:
            if term == "GM":
                frac = (gm + 0.5 + 0.5 * rng.uniform(-1, 1)) / max(1, structure.count("GM"))
                x0 += [level + rng.normal(0, 1.5), t_lo + frac * (t_hi - t_lo)]
                gm += 1
            else:
                x0.append(level + rng.normal(0, 2.0))
        bounds = []
        for term in structure:
            bounds += [(-40, 40)] + ([(t_lo, t_hi)] if term == "GM" else [])
        r = minimize(objective, np.array(x0), method="L-BFGS-B", bounds=bounds)
        if best is None or r.fun < best.fun:
            best = r
    return unpack(best.x, structure), best.fun


def names(structure):
    out, g = [], 0
    for term in structure:
        if term == "GM":
            g += 1
            out += ["GM%d sigma" % g, "GM%d tau" % g]
        else:
            out.append(term)
    return out
