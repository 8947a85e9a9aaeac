// Overlapping Allan deviation of a rate signal with confidence intervals, and the fit of the IEEE Std 952
// noise coefficients to it.
//
//   sigma^2(tau) = 1/(2 tau^2 (M - 2m)) sum_k (theta_{k+2m} - 2 theta_{k+m} + theta_k)^2,  tau = m dt
//
// with theta the integrated rate (M = n + 1 phase points). Intervals are chi-square with the equivalent
// degrees of freedom of NIST SP 1065 Table 5 for the noise type that dominates at each tau (identified from
// the local slope of the curve).
//
// Fitted model (IEEE Std 952 Annex C, eq. C.41 terms):
//   sigma^2(tau) = 3 Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + K^2 tau/3 + R^2 tau^2/2
// by non-negative least squares on the relative residual sigma_model^2/sigma^2 - 1, weighted by edf.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace gyrosid {

struct AllanOptions {
  int points_per_decade = 10;       // cluster sizes m log-spaced
  double max_tau_fraction = 1.0 / 3.0;  // largest tau as a fraction of the record length
  double confidence = 0.683;        // two-sided interval
  std::string validate() const;
};

struct AllanPoint {
  double tau_s = 0.0;
  double adev = 0.0;     // same unit as the input rate
  double ci_low = 0.0;
  double ci_high = 0.0;
  double edf = 0.0;      // equivalent chi-square degrees of freedom
  std::size_t terms = 0; // number of second differences averaged
  int alpha = 0;         // identified power-law noise exponent of frequency (2 = white PM ... -2 = random walk FM)
};

// `rate` uniformly sampled at interval dt_s.
std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& rate, double dt_s,
                                                    const AllanOptions& options = {});

// Equivalent degrees of freedom of the overlapping Allan variance (NIST SP 1065 Table 5); n_phase = M.
double allan_edf(int alpha, double n_phase, double m);

struct AllanCoefficients {
  // Units follow the input rate unit u (e.g. rad/s): Q in u*s, N in u*sqrt(s), B in u, K in u/sqrt(s),
  // R in u/s.
  double quantization = 0.0;
  double angle_random_walk = 0.0;
  double bias_instability = 0.0;
  double rate_random_walk = 0.0;
  double rate_ramp = 0.0;
  double relative_rms_residual = 0.0;  // rms of sigma_model^2/sigma^2 - 1 over the fitted points
};

struct AllanFitTerms {
  bool quantization = true, angle_random_walk = true, bias_instability = true, rate_random_walk = true,
       rate_ramp = true;
};

AllanCoefficients fit_allan(const std::vector<AllanPoint>& curve, AllanFitTerms terms = {});
double allan_model_variance(const AllanCoefficients& c, double tau_s);

// A single Gauss-Markov process (sigma, tau_c), optionally plus white noise and a rate random walk, fitted
// to a curve: log-grid search over tau_c with the variances solved by NNLS, refined by golden section.
struct GaussMarkovFit {
  double sigma = 0.0;
  double tau_s = 0.0;
  double angle_random_walk = 0.0;
  double rate_random_walk = 0.0;  // K, u/sqrt(s)
  double relative_rms_residual = 0.0;
};
GaussMarkovFit fit_gauss_markov(const std::vector<AllanPoint>& curve, bool with_white_noise, bool with_random_walk = false);

}  // namespace gyrosid
