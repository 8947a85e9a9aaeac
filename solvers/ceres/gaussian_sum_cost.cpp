#include "solvers/ceres/gaussian_sum_cost.h"

#include <cmath>

namespace gyrosid {

GaussianSumCost::GaussianSumCost(Eigen::MatrixXd x, Eigen::VectorXd y, int node_count, const Baseline* baseline)
    : x_(std::move(x)), y_(std::move(y)), nodes_(node_count), dim_(static_cast<int>(x_.cols())), baseline_(baseline) {
  set_num_residuals(static_cast<int>(y_.size()));
  auto* sizes = mutable_parameter_block_sizes();
  sizes->assign(static_cast<std::size_t>(nodes_), 2 * dim_ + 1);
  if (baseline_) sizes->push_back(baseline_->parameters);
}

bool GaussianSumCost::Evaluate(double const* const* p, double* residuals, double** jacobians) const {
  const int n = static_cast<int>(y_.size()), d = dim_, block = 2 * d + 1;
  std::vector<double> row(static_cast<std::size_t>(d)), u(static_cast<std::size_t>(d)), grad;
  if (baseline_) grad.resize(static_cast<std::size_t>(baseline_->parameters));
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < d; ++k) row[static_cast<std::size_t>(k)] = x_(i, k);
    double f = -y_(i);
    if (baseline_) {
      const bool want = jacobians && jacobians[nodes_];
      f += baseline_->evaluate(row.data(), p[nodes_], want ? grad.data() : nullptr);
      if (want) {
        for (int k = 0; k < baseline_->parameters; ++k) jacobians[nodes_][i * baseline_->parameters + k] = grad[static_cast<std::size_t>(k)];
      }
    }
    for (int j = 0; j < nodes_; ++j) {
      const double* c = p[j];
      const double* rho = p[j] + d;
      const double w = p[j][2 * d];
      double z = 0.0;
      for (int k = 0; k < d; ++k) {
        const double uk = (row[static_cast<std::size_t>(k)] - c[k]) / std::exp(rho[k]);
        u[static_cast<std::size_t>(k)] = uk;
        z += uk * uk;
      }
      const double phi = std::exp(-z);
      f += w * phi;
      if (jacobians && jacobians[j]) {
        double* jr = jacobians[j] + i * block;
        for (int k = 0; k < d; ++k) {
          const double uk = u[static_cast<std::size_t>(k)];
          jr[k] = w * phi * 2.0 * uk / std::exp(rho[k]);
          jr[d + k] = w * phi * 2.0 * uk * uk;
        }
        jr[2 * d] = phi;
      }
    }
    residuals[i] = f;
  }
  return true;
}

}  // namespace gyrosid
