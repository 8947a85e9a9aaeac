// Fisher information of a linear calibration model along a trajectory, with the sensor's noise model, and
// the linearised parameter covariance it implies.
//
// Noise (noise/processes.h): white rate noise of density N (angle random walk), first-order Gauss-Markov
// processes (those of bias instability included), rate random walk K. An observation standing for
// w_k seconds carries white noise of variance N^2 / w_k. Gauss-Markov processes correlated over less than
// the observation spacing add white noise of the same long-term Allan variance, 2 sigma^2 tau / w_k; the
// slower ones and the random walk are states of a Kalman filter whose standardised innovations whiten the
// regressor columns, so that  W' W = A' Sigma^-1 A  without an N x N covariance (white noise alone: W =
// A sqrt(w) / N). Quantization noise and rate ramp are left out (their effect on a calibration is below
// the white noise's for averaging times beyond a second, and a ramp is a drift, not a noise).
//
// With a Gaussian prior theta ~ N(m, L L') - independent scales s (L = diag(s), m = 0) for a model fitted
// afresh, or an existing calibration's posterior when a design asks what a new recording adds to it - the
// parameters in prior units z = L^-1 (theta - m) have the posterior covariance P~ = (W~'W~ + I)^-1,
// W~ = W L (what designs minimise). The calibration is the regularised least-squares fit with the same prior
// (the RBF proxy's prior is its regularisation; the physics models' prior is so wide that only directions no
// sample determines feel it): its covariance is the sandwich L P~ W~'W~ P~ L', its expected estimate on
// noise-free data gives the bias of the model class.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "noise/processes.h"

namespace gyrosid::design {

struct NoiseSpec {
  double white_psd = 0.0;            // N^2, rad^2/s
  std::vector<GaussMarkov> markov;   // every Gauss-Markov component, bias instability's included
  double rrw_psd = 0.0;              // K^2, rad^2/s^3
  static NoiseSpec of(const NoiseOptions& options);
  bool any() const { return white_psd > 0 || !markov.empty() || rrw_psd > 0; }
};

// Rows of [a | extra] whitened under the noise: `a` has one row per observation at times `t_s` (ascending,
// repeats allowed) standing for `weight_s` seconds each.
// `log_determinant` (when not null): sum_k log s_k of the innovation variances, the Gaussian log-likelihood's
// determinant term.
Eigen::MatrixXd whiten(const Eigen::MatrixXd& a, const std::vector<double>& t_s, const Eigen::VectorXd& weight_s,
                       const NoiseSpec& noise, double* log_determinant = nullptr);

// The Gaussian prior of the parameters: mean m and a square root L of the covariance (diagonal for
// independent scales).
struct Prior {
  Eigen::VectorXd mean;
  Eigen::MatrixXd root;
  static Prior independent(const Eigen::VectorXd& sd);
  Eigen::Index size() const { return root.rows(); }
};

// The linearised calibration, in prior units z = L^-1 (theta - m) (well conditioned: every eigenvalue of the
// posterior precision is >= 1).
struct LinearEstimate {
  Prior prior;
  Eigen::MatrixXd posterior;   // P~ = (W~'W~ + I)^-1
  Eigen::MatrixXd estimator;   // P~ W~'W~ P~: covariance of the calibration's estimate
  Eigen::VectorXd expected;    // P~ W~' (e~ - W m): its estimate on noise-free data, when a target was given
  double log_det_information = 0.0;  // log det(W~'W~ + I)
  // Back to model units.
  Eigen::MatrixXd posterior_covariance() const { return prior.root * posterior * prior.root.transpose(); }
  Eigen::MatrixXd estimator_covariance() const { return prior.root * estimator * prior.root.transpose(); }
  Eigen::VectorXd expected_theta() const { return prior.mean + prior.root * expected; }
};

// `whitened` is whiten([A | e]) when `has_target`, else whiten(A).
LinearEstimate linear_estimate(const Eigen::MatrixXd& whitened, const Prior& prior, bool has_target);

}  // namespace gyrosid::design
