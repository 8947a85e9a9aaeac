// The hybrid calibration's RBF network as the calibration itself would set it up on one trajectory, so that a
// design's prediction is for the network that will actually be fitted, not for a fixed dictionary.
//
// The calibration (solvers/bayes/hybrid_fit.cpp, bayes_fit.h) normalises (rate, temperature) by the
// recording's range onto [-1, 1], puts its nodes on a farthest-point subset of the recording's inputs, and
// chooses the nodes' common widths (one per input) and the weights' prior precision alpha by maximising the
// evidence, the physics columns having a flat prior and the noise being known (noise=given: beta = 1).
// Here the recording is not there yet, only the sensor's deterministic error y0 along the trajectory and its
// noise model, so the widths and alpha maximise the EXPECTED log evidence over the noise, y = y0 + e:
//
//   with whitened columns projected off the physics' span (Phi_p, y0_p; evidence.h), S = Phi_p' Phi_p =
//   V diag(lambda) V', b = V' Phi_p' y0_p and C = I + Phi_p Phi_p' / alpha (Woodbury),
//     2 log p(y) = -y_p' C^-1 y_p - log|C| + const,  y_p' C^-1 y_p = |y_p|^2 - sum_i (V' Phi_p' y_p)_i^2 / (alpha + lambda_i)
//     E[y_p' C^-1 y_p] = y0_p' C^-1 y0_p + tr C^-1,   tr C^-1 = N' - sum_i lambda_i / (alpha + lambda_i)
//   so  2 E log p = sum_i [log alpha - log(alpha + lambda_i)] - |y0_p|^2 + sum_i b_i^2 / (alpha + lambda_i)
//                   - N' + gamma(alpha) + const,           gamma = sum_i lambda_i / (alpha + lambda_i).
// Without the noise's term (-N' + gamma) the evidence of noise-free data turns the network off wherever the
// signal along an eigendirection is below the noise (per direction the optimum prior variance is b^2/lambda - 1
// instead of b^2/lambda): what a noise-free pilot fit did (experiments/trajectory_design README, 2026-11-24).
//
// The search follows bayes_fit.cpp's: a scan of one common width, then a bounded search of the per-input
// widths (derivative-free here), alpha by a one-dimensional search at every width.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "design/information.h"
#include "design/observations.h"

namespace gyrosid::design {

// The search's settings; defaults are the calibration's (BayesFitOptions).
struct NetworkSearchOptions {
  int nodes = 200;                                   // farthest-point centres among the trajectory's inputs
  int scan = 6;                                      // common widths tried, log-spaced over [scan_min, scan_max]
  double scan_min = 0.06, scan_max = 1.0;
  double min_width = 0.02, max_width = 4.0;          // normalised units
  int evaluations = 30;                              // per-input width search
  // Hyperparameters given instead of searched (a fitted calibration's, to predict for the network it chose):
  // widths (2, normalised; empty: searched) and the weights' prior sd (0: alpha by the expected evidence).
  Eigen::RowVectorXd given_widths;
  double given_prior_sd_radps = 0.0;
  std::string validate() const;
};

// Gaussian nodes on (rate rad/s, probe temperature deg C) normalised as x~ = (x - offset) / scale.
struct NetworkNodes {
  Eigen::Vector2d offset = Eigen::Vector2d::Zero(), scale = Eigen::Vector2d::Ones();
  Eigen::MatrixXd centres;     // M x 2, normalised
  Eigen::RowVectorXd widths;   // 2, normalised, shared by every node
  double prior_sd_radps = 0.0; // 1 / sqrt(alpha): the weights' prior standard deviation
  double effective_parameters = 0.0;  // gamma at the chosen alpha
  double expected_log_evidence = 0.0; // 2 E log p up to terms independent of the network (above)
  Eigen::MatrixXd columns(const Signals& inputs) const;  // N x M
};

// Projection off the span of the physics' whitened columns (flat prior), rank-safe (column-pivoted QR; a
// trajectory may leave some physics column undetermined), by the thin Q (N x rank, never N x N).
class PhysicsProjection {
 public:
  explicit PhysicsProjection(const Eigen::MatrixXd& physics_whitened);
  void project(Eigen::MatrixXd& x) const { x -= q_ * (q_.transpose() * x); }
  double residual_dof() const { return static_cast<double>(q_.rows() - q_.cols()); }  // N' = N - rank

 private:
  Eigen::MatrixXd q_;
};

// The expected evidence of one network (widths fixed) for the whitened, projected problem; alpha maximises it.
class ExpectedEvidence {
 public:
  // phi_p: whitened network columns projected off the physics' span; y0_p: the noise-free target, same;
  // residual_dof: N' = observations - physics rank.
  ExpectedEvidence(const Eigen::MatrixXd& phi_p, const Eigen::VectorXd& y0_p, double residual_dof);
  double at(double log_alpha) const;   // 2 E log p (up to network-independent terms)
  double gamma(double log_alpha) const;
  // The maximising log alpha (a grid over the eigenvalues' range, then golden-section refinement).
  double best_log_alpha() const;

 private:
  Eigen::VectorXd lambda_, b2_;
  double y2_ = 0.0, dof_ = 0.0;
};

// Widths and prior of the network the calibration would fit along `o` (its noise-free target o.true_error),
// the physics' columns `physics` (N x P, flat prior) along o, the sensor's noise `noise`.
NetworkNodes expected_evidence_network(const Observations& o, const Eigen::MatrixXd& physics, const NoiseSpec& noise,
                                       const NetworkSearchOptions& options);

}  // namespace gyrosid::design
