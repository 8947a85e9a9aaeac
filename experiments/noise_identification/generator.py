"""An independent generator of composite gyro noise (numpy only; it shares no code with gyrosid's simulator).

Rate samples are interval means at dt of the sum of
  quantization Q   white angle noise e_k ~ N(0, Q^2): rate (e_{k+1} - e_k) / dt          (IEEE Std 952 Q)
  white N          N(0, N^2 / dt)
  flicker B        spectral synthesis: two-sided PSD B^2 / (2 pi |f|) over [1 / (4 T), fs / 2] of a record
                   twice as long, its first half kept (the IEEE convention: Allan floor (2 ln 2 / pi) B^2)
  random walk K    Brownian motion of intensity K, interval means (trapezoid on a 10x finer grid)
  Gauss-Markov     Ornstein-Uhlenbeck (sigma, tau) simulated on a 10x finer grid by its exact AR(1)
                   transition, then block means of 10
Units: the rate unit u (deg/h here) and seconds; Q in u s, N in u sqrt(s), B in u, K in u / sqrt(s).
"""
import numpy as np


def composite(n, dt, seed, Q=0.0, N=0.0, B=0.0, K=0.0, gauss_markov=()):
    rng = np.random.default_rng(seed)
    y = np.zeros(n)
    if Q > 0:
        e = Q * rng.standard_normal(n + 1)
        y += np.diff(e) / dt
    if N > 0:
        y += N / np.sqrt(dt) * rng.standard_normal(n)
    if B > 0:
        y += flicker(n, dt, B, rng)
    fine = 10
    h = dt / fine
    if K > 0:
        w = np.concatenate([[0.0], np.cumsum(K * np.sqrt(h) * rng.standard_normal(n * fine))])
        seg = 0.5 * (w[:-1] + w[1:])  # mean over each fine step
        y += seg.reshape(n, fine).mean(axis=1)
    for sigma, tau in gauss_markov:
        phi = np.exp(-h / tau)
        x = np.empty(n * fine)
        x0 = sigma * rng.standard_normal()
        eps = sigma * np.sqrt(1.0 - phi * phi) * rng.standard_normal(n * fine)
        # AR(1) recursion through scipy-free filtering: x_k = phi x_{k-1} + eps_k
        from scipy.signal import lfilter
        x[:] = lfilter([1.0], [1.0, -phi], eps, zi=[phi * x0])[0]
        y += x.reshape(n, fine).mean(axis=1)
    return y


def flicker(n, dt, B, rng):
    m = 2 * n
    f = np.fft.rfftfreq(m, dt)
    amp = np.zeros_like(f)
    # Two-sided PSD S(f) = B^2 / (2 pi |f|); a real series of m samples with rfft coefficients c_k has
    # E|c_k|^2 = m S(f_k) / dt for 0 < f_k < fs/2.
    amp[1:] = np.sqrt(m * B * B / (2.0 * np.pi * f[1:]) / dt / 2.0)
    c = amp * (rng.standard_normal(len(f)) + 1j * rng.standard_normal(len(f)))
    c[0] = 0.0
    c[-1] = c[-1].real * np.sqrt(2.0)
    x = np.fft.irfft(c, m)
    return x[:n]


def oadev(y, dt, ms):
    """Overlapping Allan variance at cluster sizes ms (the textbook formula, in numpy)."""
    x = np.concatenate([[0.0], np.cumsum(y - y.mean()) * dt])
    out = []
    for m in ms:
        d = x[2 * m:] - 2 * x[m:-m] + x[:-2 * m]
        out.append(np.mean(d * d) / (2 * (m * dt) ** 2))
    return np.array(out)
