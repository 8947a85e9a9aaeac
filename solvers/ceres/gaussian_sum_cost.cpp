#include "solvers/ceres/gaussian_sum_cost.h"

#include <cmath>

#include "model/gaussian_node.h"

namespace gyrosid {

GaussianSumCost::GaussianSumCost(Eigen::MatrixXd x, Eigen::VectorXd y, int node_count, const Baseline* baseline)
    : x_(std::move(x)), y_(std::move(y)), nodes_(node_count), dim_(static_cast<int>(x_.cols())), baseline_(baseline) {
  set_num_residuals(static_cast<int>(y_.size()));
  auto* sizes = mutable_parameter_block_sizes();
  sizes->assign(static_cast<std::size_t>(nodes_), 2 * dim_ + 1);
  if (baseline_) sizes->push_back(baseline_->parameters);
}

bool GaussianSumCost::Evaluate(double const* const* p, double* residuals, double** jacobians) const {
  const int n = static_cast<int>(y_.size()), d = dim_, block = static_cast<int>(NodeBlock<double>::size(d));
  std::vector<double> row(static_cast<std::size_t>(d)), grad;
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
      f += node_output(row.data(), {p[j], d}, jacobians && jacobians[j] ? jacobians[j] + i * block : nullptr);
    }
    residuals[i] = f;
  }
  return true;
}

}  // namespace gyrosid
