// A gyro's rate noise as a composite of independent stochastic processes (IEEE Std 952 Annex C, thesis eq 3.5
// and eqs 3.52-3.55), in the data's rate unit u (deg/h at the command line). For interval-mean samples - what
// a gyro outputs - each term's Allan variance at averaging time tau is
//
//   quantization Q       3 Q^2 / tau^2          white angle noise of variance Q^2          (Q in u s)
//   low-pass filter F   -3 F^2 / tau^2          a filter on the white noise, beyond its span (F in u s)
//   white rate N         N^2 / tau              angle random walk                          (N in u sqrt(s))
//   flicker B            (2 ln 2 / pi) B^2      bias instability                           (B in u)
//   rate random walk K   K^2 tau / 3                                                       (K in u / sqrt(s))
//   rate ramp R          R^2 tau^2 / 2          deterministic                              (R in u / s)
//   Gauss-Markov (s, T)  (2 s^2 T / tau) [1 - (T / 2 tau)(3 - 4 e^{-tau/T} + e^{-2 tau/T})]   (s in u, T in s)
//
// The phase (integrated rate) x of each process has a generalised covariance C(h): the covariance of two
// combinations sum_i g_i x(t_i), sum_j g'_j x(t'_j) whose weights annihilate constants and lines (sum g = sum
// g t = 0, as every second difference of the Allan variance does) is sum_ij g_i g'_j C(t_i - t'_j), with
//
//   white        -N^2 |h| / 2                     (x a Brownian motion)
//   quantization  Q^2 [h = 0]                     (white phase)
//   filter       -F^2 [h = 0]
//   flicker       B^2 h^2 ln|h| / (2 pi)          (gives the flat (2 ln 2 / pi) B^2 above)
//   random walk   K^2 |h|^3 / 12                  (x an integrated Brownian motion)
//   Gauss-Markov -s^2 T^2 (|h|/T - 1 + e^{-|h|/T}) (x an integrated Ornstein-Uhlenbeck process)
//
// The ramp is no covariance but a mean: every second difference of its phase is R tau^2.
//
// The filter term is exact, not a fit: white noise of density N through a low-pass filter whose normalised
// autocorrelation r(l) has unit sum has the phase covariance -N^2/2 (|.| * r)(h), which equals the white
// one wherever |h| exceeds the filter's span and differs at h = 0 by -N^2 kappa dt, kappa = sum_{l>0} l r(l).
// Beyond the span the Allan variance is therefore N^2/tau - 3 N^2 kappa dt / tau^2: F^2 = N^2 kappa dt (a
// first-order filter of time constant T_f has kappa dt = T_f / 2). A sensor's anti-alias or averaging filter
// thus bends the short taus by a term that fades as 1/tau, and the fit can carry it instead of leaving the
// taus out.
#pragma once

#include <string>
#include <vector>

namespace gyrosid {

struct MarkovTerm {
  double sigma = 0.0;  // stationary standard deviation, u
  double tau_s = 0.0;  // correlation time, s
};

struct CompositeNoise {
  double quantization = 0.0;  // Q
  double filter = 0.0;        // F
  double white = 0.0;         // N
  double flicker = 0.0;       // B
  double random_walk = 0.0;   // K
  double ramp = 0.0;          // R
  std::vector<MarkovTerm> gauss_markov;

  double allan_variance(double tau_s) const;
  // C(h) above for h != 0 (the quantization and filter delta is added by the caller where two sample times
  // coincide: its weight is point_variance()).
  double phase_covariance(double h_s) const;
  double point_variance() const { return quantization * quantization - filter * filter; }
  bool has_covariance_tail() const { return flicker > 0 || !gauss_markov.empty(); }
  std::string describe(const std::string& unit) const;  // "N 120 u sqrt(s), GM (s 40 u, T 3.1 s)"
  CompositeNoise scaled(double factor) const;           // every coefficient times factor (a change of rate unit)
};

struct NoiseOptions;
// The simulator's and the designer's noise (noise/processes.h) from a composite in rad/s: white, flicker (over
// the simulator's default band), random walk, ramp and Gauss-Markov terms; quantization and a filter term act
// at the shortest taus only and are not carried (said in `left_out`, when not null).
NoiseOptions noise_options_of(const CompositeNoise& model_radps, std::string* left_out = nullptr);

inline constexpr double kFlickerAllanFactor = 0.441271200305303;  // 2 ln 2 / pi

}  // namespace gyrosid
