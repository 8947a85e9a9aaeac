// The Gaussian posterior of a model that is linear in its weights - the predictive uncertainty of a
// calibration (issue 11), and what trajectory design (src/design) needs to ask what a new recording would
// add:
//
//   output(x) = h(x)' w,   w ~ N(mean, P),   P = L L'   (L lower triangular, the Cholesky factor)
//   sigma(x)  = sqrt(|L' h(x)|^2 + s_m^2)                the standard deviation of the estimated output:
//               the posterior's, and s_m the model-class error the training data revealed (0 if none)
//
// A new experiment with regressor rows H and white noise of variance s^2 per sample would move
// the precision to P^-1 + H'H / s^2 (for coloured noise: H and the data whitened by the noise model).
// Units: weights and outputs in rad/s per unit regressor; noise_sigma_radps is the per-sample standard
// deviation of the white part of the training recording's noise.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace gyrosid {

struct WeightPosterior {
  Eigen::MatrixXd root;             // L (M x M, lower triangular): P = L L'
  double noise_sigma_radps = 0.0;   // per-sample white noise of the training data
  double model_error_radps = 0.0;   // misfit the training data revealed (solvers/bayes/model_error.h), in sigma
  nlohmann::json noise_model;       // the coloured noise model trained under, if any (noise/state_space.h)

  Eigen::Index size() const { return root.rows(); }
  Eigen::MatrixXd covariance() const { return root * root.transpose(); }
  // From a covariance matrix (symmetric positive semi-definite; a round-off jitter is added if needed).
  static WeightPosterior of_covariance(const Eigen::MatrixXd& p, double noise_sigma);
  // sigma of h' w for each row of h (N x M): sqrt(h' P h + model_error^2).
  Eigen::VectorXd sigma(const Eigen::MatrixXd& h) const;
  // Scales the weights' units by `factor` (e.g. from the unit-RMS training target to rad/s).
  void scale(double factor);

  nlohmann::json to_json() const;
  static WeightPosterior from_json(const nlohmann::json& j, Eigen::Index weights, const std::string& source);
};

}  // namespace gyrosid
