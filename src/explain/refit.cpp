#include "explain/refit.h"

#include <ceres/ceres.h>
#include <nlopt.hpp>

#include <cmath>
#include <functional>

#include "core/error.h"
#include "explain/linear_fit.h"

namespace gyrosid::explain {
namespace {

// Residuals W (y - X(tau) beta) over the whitened training samples. Blocks: beta (kept columns), then one
// log(tau) per time constant. The beta Jacobian is -W X; a log(tau) Jacobian is a central difference.
class RefitCost : public ceres::CostFunction {
 public:
  RefitCost(const ExplainInput& in, const Eigen::VectorXd& yw, ModelSpec model, std::vector<TimeConstant> taus,
            std::vector<Eigen::Index> kept, const TermScaling& sc, const Whitener& w)
      : in_(in), yw_(yw), model_(std::move(model)), taus_(std::move(taus)), kept_(std::move(kept)), sc_(sc), w_(w) {
    set_num_residuals(static_cast<int>(yw.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(kept_.size()));
    for (std::size_t k = 0; k < taus_.size(); ++k) mutable_parameter_block_sizes()->push_back(1);
  }

  // Whitened design (kept columns) with the given log time constants.
  Eigen::MatrixXd design(const std::vector<double>& log_tau) const {
    ModelSpec m = model_;
    for (std::size_t k = 0; k < taus_.size(); ++k) {
      const double tau = std::exp(log_tau[k]);
      if (taus_[k].term < 0) m.lag_tau_s = tau;
      else m.terms[static_cast<std::size_t>(taus_[k].term)].tau_s = tau;
    }
    const Eigen::MatrixXd x = w_.apply(design_matrix(m.terms, in_.signals, coil_temperature(in_.signals, m.lag_tau_s), sc_));
    Eigen::MatrixXd out(x.rows(), static_cast<Eigen::Index>(kept_.size()));
    for (std::size_t c = 0; c < kept_.size(); ++c) out.col(static_cast<Eigen::Index>(c)) = x.col(kept_[c]);
    return out;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Index p = static_cast<Eigen::Index>(kept_.size());
    const Eigen::Map<const Eigen::VectorXd> beta(parameters[0], p);
    std::vector<double> log_tau(taus_.size());
    for (std::size_t k = 0; k < taus_.size(); ++k) log_tau[k] = parameters[1 + k][0];
    const Eigen::MatrixXd x = design(log_tau);
    Eigen::Map<Eigen::VectorXd> r(residuals, yw_.size());
    r = yw_ - x * beta;
    if (!jacobians) return true;
    if (jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> j(jacobians[0], yw_.size(), p);
      j = -x;
    }
    for (std::size_t k = 0; k < taus_.size(); ++k) {
      if (!jacobians[1 + k]) continue;
      const double h = 1e-4;
      std::vector<double> up = log_tau, down = log_tau;
      up[k] += h, down[k] -= h;
      Eigen::Map<Eigen::VectorXd> j(jacobians[1 + k], yw_.size());
      j = -(design(up) - design(down)) * beta / (2.0 * h);
    }
    return true;
  }

 private:
  const ExplainInput& in_;
  const Eigen::VectorXd& yw_;
  ModelSpec model_;
  std::vector<TimeConstant> taus_;
  std::vector<Eigen::Index> kept_;
  const TermScaling& sc_;
  const Whitener& w_;
};

}  // namespace

namespace {

ModelSpec at_time_constants(ModelSpec m, const std::vector<TimeConstant>& taus, const std::vector<double>& log_tau) {
  for (std::size_t k = 0; k < taus.size(); ++k) {
    if (taus[k].term < 0) m.lag_tau_s = std::exp(log_tau[k]);
    else m.terms[static_cast<std::size_t>(taus[k].term)].tau_s = std::exp(log_tau[k]);
  }
  return m;
}

// Variable projection: the time constants by BOBYQA, every linear coefficient solved exactly inside.
void optimise_time_constants(const ExplainInput& in, const Eigen::VectorXd& yw, const ModelSpec& model, const std::vector<TimeConstant>& taus,
                             const TermScaling& sc, const Whitener& w, std::vector<double>& log_tau) {
  if (taus.empty()) return;
  const double duration = in.signals.t_s.back() - in.signals.t_s.front();
  std::vector<double> lo, hi;
  for (double v : log_tau) {
    lo.push_back(std::max(0.0, v - std::log(10.0)));
    hi.push_back(std::min(std::log(std::max(10.0, 2.0 * duration)), v + std::log(10.0)));
  }
  std::function<double(const std::vector<double>&)> rss = [&](const std::vector<double>& x) {
    const ModelSpec m = at_time_constants(model, taus, x);
    return fit_whitened(w.apply(design_matrix(m.terms, in.signals, coil_temperature(in.signals, m.lag_tau_s), sc)), yw).rss;
  };
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(log_tau.size()));
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_xtol_abs(1e-4);
  opt.set_maxeval(100 * static_cast<int>(log_tau.size()));
  opt.set_min_objective([](const std::vector<double>& x, std::vector<double>&, void* f) {
    return (*static_cast<std::function<double(const std::vector<double>&)>*>(f))(x);
  }, &rss);
  double value = 0.0;
  try {
    opt.optimize(log_tau, value);
  } catch (const std::exception&) {
    // BOBYQA may stop on roundoff; log_tau holds its best point.
  }
}

}  // namespace

RefitResult refit(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& model, bool refine_lag, const TermScaling& sc,
                  const Whitener& w) {
  RefitResult out;
  const Eigen::VectorXd yw = w.apply(y);
  for (std::size_t t = 0; t < model.terms.size(); ++t) {
    if (model.terms[t].kind == TermKind::warmup) out.time_constants.push_back({static_cast<int>(t), model.terms[t].tau_s});
  }
  if (refine_lag && model.lag_tau_s > 0) out.time_constants.push_back({-1, model.lag_tau_s});
  std::vector<double> log_tau;
  for (const auto& t : out.time_constants) log_tau.push_back(std::log(t.tau_s));
  optimise_time_constants(in, yw, model, out.time_constants, sc, w, log_tau);
  out.model = at_time_constants(model, out.time_constants, log_tau);

  // Linear coefficients at the optimum; dependent columns are dropped before the joint problem.
  const Eigen::MatrixXd x0 = w.apply(design_matrix(out.model.terms, in.signals, coil_temperature(in.signals, out.model.lag_tau_s), sc));
  const WhitenedFit start = fit_whitened(x0, yw);
  out.kept = start.kept;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index c = 0; c < x0.cols(); ++c) {
    if (start.kept[static_cast<std::size_t>(c)]) kept.push_back(c);
  }
  std::vector<double> beta(kept.size());
  for (std::size_t c = 0; c < kept.size(); ++c) beta[c] = start.beta(kept[c]);

  // The joint problem in Ceres: a Levenberg-Marquardt polish from the projected optimum, then the covariance
  // of every parameter.
  ceres::Problem problem;
  auto* cost = new RefitCost(in, yw, model, out.time_constants, kept, sc, w);
  std::vector<double*> blocks{beta.data()};
  for (auto& v : log_tau) blocks.push_back(&v);
  problem.AddResidualBlock(cost, nullptr, blocks);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 20;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-10;
  ceres::Solver::Summary summary;
  if (!kept.empty()) ceres::Solve(options, &problem, &summary);
  out.termination = kept.empty() ? "no parameters" : ceres::TerminationTypeToString(summary.termination_type);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.model = at_time_constants(model, out.time_constants, log_tau);
  for (std::size_t k = 0; k < out.time_constants.size(); ++k) out.time_constants[k].tau_s = std::exp(log_tau[k]);

  out.beta = Eigen::VectorXd::Zero(x0.cols());
  out.beta_sigma = Eigen::VectorXd::Zero(x0.cols());
  for (std::size_t c = 0; c < kept.size(); ++c) out.beta(kept[c]) = beta[c];
  const double dof = std::max(1.0, static_cast<double>(yw.size()) - static_cast<double>(kept.size() + log_tau.size()));
  const double sigma2 = kept.empty() ? yw.squaredNorm() / dof : 2.0 * summary.final_cost / dof;
  out.residual_sigma = std::sqrt(sigma2);

  if (!kept.empty()) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs;
    for (double* b : blocks) pairs.emplace_back(b, b);
    out.covariance_ok = covariance.Compute(pairs, &problem);
    if (out.covariance_ok) {
      std::vector<double> cov(kept.size() * kept.size());
      covariance.GetCovarianceBlock(beta.data(), beta.data(), cov.data());
      for (std::size_t c = 0; c < kept.size(); ++c) out.beta_sigma(kept[c]) = std::sqrt(std::max(0.0, sigma2 * cov[c * kept.size() + c]));
      for (std::size_t k = 0; k < log_tau.size(); ++k) {
        double v = 0.0;
        covariance.GetCovarianceBlock(&log_tau[k], &log_tau[k], &v);
        const double s = std::sqrt(std::max(0.0, sigma2 * v));
        out.time_constants[k].low_s = std::exp(log_tau[k] - 1.96 * s);
        out.time_constants[k].high_s = std::exp(log_tau[k] + 1.96 * s);
      }
    }
  }
  return out;
}

}  // namespace gyrosid::explain
