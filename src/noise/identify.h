// Noise identification: which composite model (noise/composite.h) a uniformly sampled rate follows, with an
// interval for every parameter - the one noise estimator that `allan`, `calibrate`, `explain` and `design` use.
//
// Moments: overlapping Allan variances s_j at octave cluster sizes m_j = 2^j up to a tenth of the record (the
// Haar wavelet variance is s_j / 2: this is the generalised method of wavelet moments of Guerrier, Skaloud,
// Stebler & Victoria-Feser, IEEE TAES 2013). Estimator: generalised least squares
//   theta = argmin (s - s(theta))' Sigma^-1 (s - s(theta)),
// with Sigma the estimates' exact covariance under the fitted model (noise/allan_covariance.h), iterated to a
// fixed point - where GMWM estimates its weight matrix from the data, which is noisy at the long taus that
// carry the slow terms. The variances of the terms enter linearly and are solved by non-negative least
// squares; only the Gauss-Markov correlation times are searched (variable projection). The covariance of
// theta is (J' Sigma^-1 J)^-1, widened by max(1, chi^2 / dof) where the data scatter more than the model
// says; a term's interval is chi-square with Satterthwaite's degrees of freedom 2 v^2 / var(v) on its
// variance v, a correlation time's is log-normal.
//
// Model order: every structure of {Q, N, B, K, R} with up to max_gauss_markov Gauss-Markov terms is fitted
// with the weight of the fullest model; the ten best by chi^2 + c p (p parameters, c = 6.63, the chi^2_1
// quantile at 0.99: a term stays when it lowers chi^2 by more than a 1 % test allows by chance) are fitted
// again each under its own weight, and the least criterion there is kept. (Schwarz's c = ln n of Andrews
// 1999 prices the slow terms by the sampling rate, not by the record's length that informs them: on real
// logs it left 3-sigma misfits at the long taus.) Physical bounds: a Gauss-Markov correlation time lies
// between twice max(dt, the shortest fitted tau) - faster, the process is white within the band - and the
// record length.
//
// Distorted short taus: a sensor's anti-alias filter or decimation correlates neighbouring samples, a tone
// or aliasing adds power, and either bends the shortest taus away from any composite model. The shortest tau is left out while its moment is
// inconsistent with the others - Hansen's C statistic, the rise of chi^2 when it is added, above the
// chi^2_1 quantile at 1 - left_out_alpha - up to max_left_out_tau_s; the result says what was left out and why.
//
// Robust option: each Allan variance from a bisquare M-estimate of the scale of the second differences
// (c = 3: 24 % breakdown, 88 % Gaussian efficiency), for recordings with outliers; its covariance is the
// classical one over that efficiency.
#pragma once

#include <Eigen/Core>

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "noise/composite.h"

namespace gyrosid {

// Which terms a model has.
struct NoiseStructure {
  bool quantization = false, filter = false, white = false, flicker = false, random_walk = false, ramp = false;
  int gauss_markov = 0;

  int parameters() const;
  std::string name() const;  // "N+B+GM+GM"; "none" for the empty structure
  // "auto" is not a structure; names from Q, F, N, B, K, R, GM (GM repeated for more), joined by '+'.
  static NoiseStructure parse(std::string_view text);  // Error naming the unknown term
  static NoiseStructure full(int gauss_markov);
  bool operator==(const NoiseStructure&) const = default;
};

struct NoiseIdOptions {
  std::string terms = "auto";         // "auto" (chosen by the criterion) or a structure, e.g. "N+B+K+GM"
  int max_gauss_markov = 3;           // auto: at most this many Gauss-Markov terms
  double max_tau_fraction = 0.1;      // the longest fitted tau, as a fraction of the record
  double min_tau_s = 0.0;             // the shortest fitted tau; 0: detected
  double max_left_out_tau_s = 1.0;    // the detection leaves out no tau above this
  double left_out_alpha = 1e-3;       // level of the C test that leaves out a short tau
  double confidence = 0.95;           // of the parameters' intervals
  bool robust = false;                // bisquare M-estimates of the Allan variances
  std::string validate() const;
};

// One reported parameter, in the data's unit (see CompositeNoise).
struct NoiseParameter {
  std::string name;  // "Q", "F", "N", "B", "K", "R", "GM1 sigma", "GM1 tau"
  double value = 0.0, sigma = 0.0, low = 0.0, high = 0.0;
};

// An octave tau of the fit: the data's Allan variance, the fitted one, and their difference over the
// estimate's standard deviation under the fitted model.
struct NoiseFitPoint {
  double tau_s = 0.0, allan_variance = 0.0, fitted = 0.0, z = 0.0;
  bool in_band = false;
};

struct NoiseCandidate {
  NoiseStructure structure;
  double chi2 = 0.0, criterion = 0.0;
  bool adequate = true;  // its J test (chi2 on its degrees of freedom) not rejected at 1 %
};

// One coordinate of the fitted parameter vector theta: a term's variance (the square of its coefficient), or
// a Gauss-Markov term's log correlation time.
struct NoiseCoordinate {
  std::string term;       // "Q", "F", "N", "B", "K", "R", "GM" (a variance) or "GM tau" (a log time)
  double tau_s = 0.0;     // Gauss-Markov: its correlation time
  double variance = 0.0;  // "GM tau": the term's variance
  double allan_variance_gradient(double tau_s) const;  // d s(tau) / d coordinate
};

struct NoiseIdentification {
  CompositeNoise model;
  NoiseStructure structure;
  std::vector<NoiseParameter> parameters;
  double fit_tau_low_s = 0.0, fit_tau_high_s = 0.0;  // the taus the fit claims
  double chi2 = 0.0, p_value = 1.0;
  int dof = 0;
  double dispersion = 1.0;  // max(1, chi2 / dof): the factor the parameters' covariance is widened by
  std::vector<NoiseFitPoint> points;
  std::vector<NoiseCandidate> candidates;  // best first
  std::string left_out;                    // why the shortest taus were left out; empty when none was
  std::vector<std::string> warnings;       // where the model does not fit
  std::size_t samples = 0;
  double dt_s = 0.0;
  bool robust = false;

  double allan_variance(double tau_s) const { return model.allan_variance(tau_s); }
  // Standard error of the fitted Allan variance at tau (delta method through theta's covariance).
  double allan_variance_sigma(double tau_s) const;

  std::vector<NoiseCoordinate> coordinates;  // theta
  Eigen::MatrixXd covariance;                // of theta: (J' Sigma^-1 J)^-1
};

class AllanPhase;
NoiseIdentification identify_noise(const AllanPhase& phase, const NoiseIdOptions& options = {});
NoiseIdentification identify_noise(std::span<const double> rate, double dt_s, const NoiseIdOptions& options = {});

}  // namespace gyrosid
