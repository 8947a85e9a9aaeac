// Ceres cost function for a chunk of samples of a Gaussian sum
//
//   r_i = b(x_i; beta) + sum_{j in nodes} w_j exp(-sum_k ((x_ik - c_jk) / exp(rho_jk))^2) - y_i
//
// with one parameter block per node, [c_1..c_d, rho_1..rho_d, w] (model/gaussian_node.h: NodeBlock, rho =
// log width), and an optional parametric baseline b with its own block (e.g. a constant, or the exponential
// decay of NIST StRD Gauss1/2). Jacobians are analytic (node_output).
// A chunk lists only the nodes it depends on, so truncated Gaussians give a sparse Jacobian.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>

#include <algorithm>
#include <functional>
#include <vector>

#include "model/gaussian_node.h"

namespace gyrosid {

// A baseline b(x; beta): returns b and fills db/dbeta (size = parameters) when gradient is non-null.
struct Baseline {
  int parameters = 0;
  std::function<double(const double* x, const double* beta, double* gradient)> evaluate;
};

class GaussianSumCost : public ceres::CostFunction {
 public:
  // x: rows of the chunk (n x d), y: targets; the cost's parameter blocks are the `node_count` node blocks
  // followed by the baseline block when `baseline` is set.
  GaussianSumCost(Eigen::MatrixXd x, Eigen::VectorXd y, int node_count, const Baseline* baseline);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  Eigen::MatrixXd x_;
  Eigen::VectorXd y_;
  int nodes_;
  int dim_;
  const Baseline* baseline_;
};

// sqrt(lambda) w_j: ridge on one node's weight (its NodeBlock's).
class WeightPrior : public ceres::CostFunction {
 public:
  WeightPrior(int dimension, double sqrt_lambda) : dim_(dimension), sqrt_lambda_(sqrt_lambda) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->assign(1, static_cast<int>(NodeBlock<double>::size(dimension)));
  }
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    r[0] = sqrt_lambda_ * NodeBlock<const double>{p[0], dim_}.weight();
    if (j && j[0]) {
      std::fill(j[0], j[0] + NodeBlock<double>::size(dim_), 0.0);
      NodeBlock<double>{j[0], dim_}.weight() = sqrt_lambda_;
    }
    return true;
  }

 private:
  Eigen::Index dim_;
  double sqrt_lambda_;
};

}  // namespace gyrosid
