// Overlapping Allan deviation of a rate signal with confidence intervals (classical or robust).
//
//   sigma^2(tau) = 1/(2 tau^2 (M - 2m)) sum_k (theta_{k+2m} - 2 theta_{k+m} + theta_k)^2,  tau = m dt
//
// with theta the integrated rate (M = n + 1 phase points). Intervals are chi-square with the equivalent
// degrees of freedom of NIST SP 1065 Table 5 for the noise type that dominates at each tau (identified from
// the local slope of the curve).
//
// The noise model fitted to it is noise/identify.h's; fit_gauss_markov below serves the whitening model's
// projection (noise/state_space.h).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace gyrosid {

struct AllanOptions {
  int points_per_decade = 10;       // cluster sizes m log-spaced
  double max_tau_fraction = 1.0 / 3.0;  // largest tau as a fraction of the record length
  double confidence = 0.683;        // two-sided interval
  bool robust = false;              // bisquare M-estimates (AllanPhase::robust_variance)
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

// The phase (integrated rate, its mean removed, summed in long double) of a uniformly sampled rate, kept
// once for Allan variances at any cluster size m (tau = m dt).
class AllanPhase {
 public:
  AllanPhase(std::span<const double> rate, double dt_s);
  std::size_t samples() const { return theta_.size() - 1; }
  double dt_s() const { return dt_; }
  double variance(std::size_t m) const;  // overlapping Allan variance
  // The same from a bisquare M-estimate of the scale of the second differences (c = 3, consistent at the
  // Gaussian): robust to outliers, at kRobustAllanEfficiency of the classical estimate's efficiency.
  double robust_variance(std::size_t m) const;
  // sum_k d_k^2 / (2 K): the Allan variance times tau^2.
  double half_mean_square(std::size_t m) const;

 private:
  double second_difference(std::size_t k, std::size_t m) const {
    return static_cast<double>(theta_[k + 2 * m] - 2.0L * theta_[k + m] + theta_[k]);
  }
  std::vector<long double> theta_;
  double dt_;
};
// Asymptotic Gaussian efficiency of robust_variance (the classical estimate's variance over its own).
inline constexpr double kRobustAllanEfficiency = 0.8773;

// `rate` uniformly sampled at interval dt_s; options.robust: AllanPhase::robust_variance.
std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& rate, double dt_s,
                                                    const AllanOptions& options = {});
std::vector<AllanPoint> overlapping_allan_deviation(const AllanPhase& phase, const AllanOptions& options = {});

// Equivalent degrees of freedom of the overlapping Allan variance (NIST SP 1065 Table 5); n_phase = M.
double allan_edf(int alpha, double n_phase, double m);

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
