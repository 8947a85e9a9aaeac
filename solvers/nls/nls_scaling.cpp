#include "solvers/nls/nls_scaling.h"

#include <ceres/ceres.h>

#include <cmath>

namespace gyrosid {

ScaledObjective::ScaledObjective(NlsProblem& problem, SolveMonitor& monitor, bool report_every_evaluation)
    : problem_(problem), monitor_(monitor), report_every_(report_every_evaluation) {
  const Eigen::VectorXd x0 = problem.free_values();
  Eigen::MatrixXd gn;
  const double f0 = problem.evaluate(x0, nullptr, &gn);
  scale_ = gn.diagonal().cwiseSqrt();
  for (Eigen::Index i = 0; i < scale_.size(); ++i) {
    if (!(scale_(i) > 0) || !std::isfinite(scale_(i))) scale_(i) = 1.0;
  }
  cost0_ = (f0 > 0 && std::isfinite(f0)) ? f0 : 1.0;
  start_ = scale_.cwiseProduct(x0);
  best_u_ = start_;
  best_ = f0 / cost0_;
}

Eigen::VectorXd ScaledObjective::scaled_lower() const { return scale_.cwiseProduct(problem_.free_lower()); }
Eigen::VectorXd ScaledObjective::scaled_upper() const { return scale_.cwiseProduct(problem_.free_upper()); }

double ScaledObjective::value(const Eigen::VectorXd& u, Eigen::VectorXd* gradient, Eigen::MatrixXd* gauss_newton) {
  const bool derivatives = gradient || gauss_newton;
  if (derivatives && cached_u_.size() == u.size() && cached_u_ == u) {
    if (gradient) *gradient = cached_gradient_;
    if (gauss_newton) *gauss_newton = cached_gn_;
    return cached_value_;
  }
  const Eigen::VectorXd x = u.cwiseQuotient(scale_);
  Eigen::VectorXd g;
  Eigen::MatrixXd h;
  const double v = problem_.evaluate(x, derivatives ? &g : nullptr, derivatives ? &h : nullptr) / cost0_;
  monitor_.evaluation();
  if (report_every_) monitor_.iteration(v * cost0_);
  if (v < best_) {
    best_ = v;
    best_u_ = u;
  }
  if (derivatives) {
    const Eigen::VectorXd inv = scale_.cwiseInverse();
    cached_u_ = u;
    cached_value_ = v;
    cached_gradient_ = inv.cwiseProduct(g) / cost0_;
    cached_gn_ = inv.asDiagonal() * h * inv.asDiagonal() / cost0_;
    if (gradient) *gradient = cached_gradient_;
    if (gauss_newton) *gauss_newton = cached_gn_;
  }
  return v;
}

void ScaledObjective::store_best() { problem_.set_free_values(best_u_.cwiseQuotient(scale_)); }

ceres::Problem ceres_problem(NlsProblem& p) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (int i = 0; i < p.block_count(); ++i) {
    NlsProblem::ParameterBlock& b = p.block(i);
    problem.AddParameterBlock(b.values.data(), b.size());
  }
  for (const auto& r : p.residual_blocks()) {
    std::vector<double*> blocks;
    for (int bi : r.blocks) blocks.push_back(p.block(bi).values.data());
    problem.AddResidualBlock(r.cost.get(), nullptr, blocks);
  }
  for (int i = 0; i < p.block_count(); ++i) {
    NlsProblem::ParameterBlock& b = p.block(i);
    if (!problem.HasParameterBlock(b.values.data())) continue;  // in no residual block
    std::vector<int> fixed;
    for (int k = 0; k < b.size(); ++k) {
      if (b.fixed[static_cast<std::size_t>(k)]) fixed.push_back(k);
    }
    if (static_cast<int>(fixed.size()) == b.size()) {
      problem.SetParameterBlockConstant(b.values.data());
    } else if (!fixed.empty()) {
      problem.SetManifold(b.values.data(), new ceres::SubsetManifold(b.size(), fixed));
    }
    for (int k = 0; k < b.size() && !b.lower.empty(); ++k) {
      if (b.fixed[static_cast<std::size_t>(k)] || static_cast<int>(fixed.size()) == b.size()) continue;
      if (std::isfinite(b.lower[static_cast<std::size_t>(k)])) problem.SetParameterLowerBound(b.values.data(), k, b.lower[static_cast<std::size_t>(k)]);
      if (std::isfinite(b.upper[static_cast<std::size_t>(k)])) problem.SetParameterUpperBound(b.values.data(), k, b.upper[static_cast<std::size_t>(k)]);
    }
  }
  return problem;
}

}  // namespace gyrosid
