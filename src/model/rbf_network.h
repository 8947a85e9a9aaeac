// Gaussian radial basis function network with a width per input per node (thesis eqs 4.1-4.5):
//
//   f(x) = b + sum_j w_j exp(-z_j(x)),   z_j(x) = sum_k (x~_k - c_jk)^2 / r_jk^2,   x~ = normalised x
//
// Centres c and widths r live in normalised input units; weights w and the optional constant b in rad/s
// (dimensionless for a relative network, below; the model file's keys keep the _radps suffix).
// A network trained by a Bayesian solver also carries the posterior of (w_1..w_m, b): regressors
// h(x) = [phi_1(x~) .. phi_m(x~), 1].
//
// Optionally the output is multiplied by one of the raw inputs (output_factor = k): F(x) = x_k f(x). With k the
// measured rate the network is a relative scale-factor error r(T, g) and F = g r the rate error it causes - the
// classical surface's form [s_T(T) + s_w(g)] g (thesis s5.3.2) with an RBF for the scale factor. Everything
// else (weights, posterior) is f's; predict, regressors and the C export apply the factor.
#pragma once

#include <Eigen/Core>

#include <optional>

#include "model/calibration_model.h"
#include "model/gaussian_node.h"
#include "model/normalizer.h"

namespace gyrosid {

class RbfNetwork : public CalibrationModel {
 public:
  RbfNetwork(std::vector<std::string> features, ModelTarget target, Normalizer normalizer);

  std::string_view kind() const override { return "rbf"; }
  using CalibrationModel::predict;
  double predict(const double* x) const override;
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<RbfNetwork> from_json(const nlohmann::json& j, std::vector<std::string> features,
                                               ModelTarget target);

  // Normalised-space evaluation of f (without the output factor) and the basis matrix Phi (N x m),
  // Phi_ij = exp(-z_j(x_i)).
  double evaluate_normalised(const double* xn) const;
  Eigen::MatrixXd basis(const Eigen::MatrixXd& xn) const;

  const WeightPosterior* posterior() const override { return weight_posterior ? &*weight_posterior : nullptr; }
  Eigen::MatrixXd regressors(const Eigen::MatrixXd& x) const override;

  Eigen::Index nodes() const { return weights.size(); }
  // Node j as the joint solvers' packed block [c, log r, w] (NodeBlock::size(d) values) and back.
  void pack_node(Eigen::Index j, double* block) const;
  void unpack_node(Eigen::Index j, const double* block);
  Eigen::Index dimension() const { return normalizer.dimension(); }

  Normalizer normalizer;
  Eigen::MatrixXd centres;  // m x d
  Eigen::MatrixXd widths;   // m x d
  Eigen::VectorXd weights;  // m
  double bias = 0.0;
  Eigen::Index output_factor = -1;  // the input the output is multiplied by (above); -1: none
  std::optional<WeightPosterior> weight_posterior;  // over (weights, bias), when trained by a Bayesian solver
};

}  // namespace gyrosid
