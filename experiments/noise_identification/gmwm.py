"""A GMWM-class reference fit in numpy/scipy (Guerrier, Skaloud, Stebler & Victoria-Feser, IEEE TAES 2013),
written for this comparison and independent of gyrosid's estimator.

Moments: the Haar MODWT wavelet variance nu_j^2 at dyadic scales tau_j = 2^(j-1) dt (computed from block
means, = half the overlapping Allan variance). Weight: diagonal, the inverse of each estimate's variance by
Percival & Walden's chi-square approximation with eta3 = max(M_j / 2^j, 1) degrees of freedom,
var(nu_j^2) = 2 nu_j^4 / eta3 (the usual GMWM choice for a quick fit). Estimate: argmin of
sum_j (nu_j^2 - nu_j^2(theta))^2 / var_j over the log-parameters by trust-region least squares, from guided
starting values over a grid of Gauss-Markov times.
"""
import numpy as np

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


def starting_values(taus, nu2, structure, gm_taus):
    """Log-parameters read off the wavelet variance where each term rules (the usual GMWM guided start):
    Q from the first scale, N from the shortest scales' white level, B from the minimum, K from the last
    scale, a Gauss-Markov term's variance from the wavelet variance near twice its start time."""
    av = 2.0 * nu2  # Allan variance
    x, g = [], 0
    for term in structure:
        if term == "Q":
            x.append(0.5 * np.log(av[0] * taus[0] ** 2 / 3.0 / 4.0))
        elif term == "N":
            x.append(0.5 * np.log(np.median(av[:4] * taus[:4])))
        elif term == "B":
            x.append(0.5 * np.log(av.min() / LN2PI / 2.0))
        elif term == "K":
            x.append(0.5 * np.log(3.0 * av[-1] / taus[-1] / 2.0))
        elif term == "GM":
            T = gm_taus[g]; g += 1
            k = np.argmin(np.abs(np.log(taus / (2.0 * T))))
            x += [0.5 * np.log(av[k] / 0.4 / 2.0), np.log(T)]
    return np.array(x)


def fit(y, dt, structure, seed=0):
    """theta (natural units, Gauss-Markov terms by ascending tau) and the objective at it: trust-region least
    squares on the weighted residuals in log-parameters, from a grid of Gauss-Markov start times (every
    ordered pair of 8 log-spaced times over the scales), the best kept."""
    from itertools import combinations
    from scipy.optimize import least_squares
    taus, nu2, eta = wavelet_variance(y, dt)
    w = np.sqrt(eta / (2.0 * nu2 ** 2))
    t_lo, t_hi = np.log(2 * dt), np.log(len(y) * dt)

    def residuals(x):
        return w * (nu2 - model_wv(unpack(x, structure), taus, structure))

    lower, upper = [], []
    for term in structure:
        lower += [-30.0] + ([t_lo] if term == "GM" else [])
        upper += [30.0] + ([t_hi] if term == "GM" else [])
    grid = np.exp(np.linspace(np.log(taus[0] * 2), np.log(taus[-1]), 8))
    k = structure.count("GM")
    best = None
    for gm_taus in combinations(grid, k):
        x0 = np.clip(starting_values(taus, nu2, structure, gm_taus), np.array(lower) + 1e-9, np.array(upper) - 1e-9)
        r = least_squares(residuals, x0, bounds=(lower, upper), method="trf", x_scale="jac", max_nfev=400)
        if best is None or r.cost < best.cost:
            best = r
    return unpack(best.x, structure), 2.0 * best.cost


def names(structure):
    out, g = [], 0
    for term in structure:
        if term == "GM":
            g += 1
            out += ["GM%d sigma" % g, "GM%d tau" % g]
        else:
            out.append(term)
    return out
