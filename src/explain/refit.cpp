#include "explain/refit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/bounded_search.h"
#include "core/error.h"
#include "explain/linear_fit.h"
#include "explain/noise_likelihood.h"
#include "solvers/common/ceres_support.h"

namespace gyrosid::explain {
namespace {

ModelSpec at_parameters(ModelSpec m, const std::vector<NonlinearFit>& taus, const std::vector<double>& log_tau) {
  for (std::size_t k = 0; k < taus.size(); ++k) {
    if (taus[k].term < 0) {
      m.lag_tau_s = std::exp(log_tau[k]);
    } else {
      Term& term = m.terms[static_cast<std::size_t>(taus[k].term)];
      term = term.with_parameter(std::exp(log_tau[k]));
    }
  }
  return m;
}

// Residuals W (y - X(tau) beta) over the whitened training samples. Blocks: beta (kept columns), then one
// log(tau) per time constant. The beta Jacobian is -W X; a log(tau) Jacobian is a central difference.
class RefitCost : public ceres::CostFunction {
 public:
  RefitCost(const ExplainInput& in, const Eigen::VectorXd& yw, ModelSpec model, std::vector<NonlinearFit> taus,
            std::vector<Eigen::Index> kept, const TermScaling& sc, const Whitener& w)
      : in_(in), yw_(yw), model_(std::move(model)), taus_(std::move(taus)), kept_(std::move(kept)), sc_(sc), w_(w) {
    set_num_residuals(static_cast<int>(yw.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(kept_.size()));
    for (std::size_t k = 0; k < taus_.size(); ++k) mutable_parameter_block_sizes()->push_back(1);
  }

  // Whitened design (kept columns) with the given log time constants.
  Eigen::MatrixXd design(const std::vector<double>& log_tau) const {
    const ModelSpec m = at_parameters(model_, taus_, log_tau);
    const Eigen::MatrixXd x = w_.apply(model_columns(m, in_.signals, sc_));
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
  std::vector<NonlinearFit> taus_;
  std::vector<Eigen::Index> kept_;
  const TermScaling& sc_;
  const Whitener& w_;
};

// Variable projection: the time constants by BOBYQA, every linear coefficient solved exactly inside.
// Returns the whitened RSS at the optimum and whether the search converged (stopped on its tolerance).
struct Projected {
  double rss = 0.0;
  bool converged = true;
};
struct ProjectionSearch {
  int max_evaluations_each = 100;
  double xtol = 1e-4;          // in log(tau)
  double initial_step = 0.0;   // in log(tau); 0: from the bounds
};
Projected optimise_parameters(const ExplainInput& in, const Eigen::VectorXd& yw, const ModelSpec& model, const std::vector<NonlinearFit>& taus,
                              const TermScaling& sc, const Whitener& w, std::vector<double>& log_tau, const ProjectionSearch& search = {}) {
  if (taus.empty()) return {whitened_rss(whiten_columns(w, model_columns(model, in.signals, sc)), yw), true};
  const double duration = in.signals.t_s.back() - in.signals.t_s.front();
  std::vector<double> lo, hi;
  for (double v : log_tau) {
    lo.push_back(std::max(0.0, v - std::log(10.0)));
    hi.push_back(std::min(std::log(std::max(10.0, 2.0 * duration)), v + std::log(10.0)));
  }
  BoundedSearchOptions bobyqa;
  bobyqa.xtol_abs = search.xtol;
  bobyqa.initial_step = search.initial_step;
  bobyqa.max_evaluations = search.max_evaluations_each * static_cast<int>(log_tau.size());
  const BoundedSearchResult r = minimize_bounded([&](const std::vector<double>& x) {
    const ModelSpec m = at_parameters(model, taus, x);
    return whitened_rss(whiten_columns(w, model_columns(m, in.signals, sc)), yw);
  }, log_tau, lo, hi, bobyqa);
  log_tau = r.x;
  return {r.value, termination_of(r) == Termination::converged};
}

std::vector<NonlinearFit> nonlinear_parameters(const ModelSpec& model, bool refine_lag) {
  std::vector<NonlinearFit> out;
  for (std::size_t t = 0; t < model.terms.size(); ++t) {
    const auto p = model.terms[t].parameter();
    if (p && p->scale) out.push_back({static_cast<int>(t), p->name, p->value});
  }
  if (refine_lag && model.lag_tau_s > 0) out.push_back({-1, "tau_s", model.lag_tau_s});
  return out;
}

// The joint problem in Ceres: a Levenberg-Marquardt polish of (beta, log tau) from the projected optimum.
ceres::Solver::Summary polish(ceres::Problem& problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 20;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-10;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary;
}

// Standard deviations of the coefficients and 95 % intervals of the nonlinear parameters (log-normal), from
// ceres::Covariance scaled by the residual variance.
void intervals(ceres::Problem& problem, const std::vector<double*>& blocks, const std::vector<Eigen::Index>& kept, double sigma2,
               RefitResult& out) {
  ceres::Covariance covariance(dense_svd_covariance());
  std::vector<std::pair<const double*, const double*>> pairs;
  for (double* b : blocks) pairs.emplace_back(b, b);
  out.covariance_ok = covariance.Compute(pairs, &problem);
  if (!out.covariance_ok) return;
  std::vector<double> cov(kept.size() * kept.size());
  covariance.GetCovarianceBlock(blocks[0], blocks[0], cov.data());
  for (std::size_t c = 0; c < kept.size(); ++c) out.beta_sigma(kept[c]) = std::sqrt(std::max(0.0, sigma2 * cov[c * kept.size() + c]));
  for (std::size_t k = 0; k + 1 < blocks.size(); ++k) {
    double v = 0.0;
    covariance.GetCovarianceBlock(blocks[k + 1], blocks[k + 1], &v);
    const double s = std::sqrt(std::max(0.0, sigma2 * v)), log_tau = *blocks[k + 1];
    out.nonlinear[k].low = std::exp(log_tau - 1.96 * s);
    out.nonlinear[k].high = std::exp(log_tau + 1.96 * s);
  }
}

}  // namespace

ProfiledFit profiled_fit(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& model, bool refine_lag, const TermScaling& sc,
                         const Whitener& w) {
  const Eigen::VectorXd yw = w.apply(y);
  const std::vector<NonlinearFit> taus = nonlinear_parameters(model, refine_lag);
  std::vector<double> log_tau;
  for (const auto& t : taus) log_tau.push_back(std::log(t.value));
  // Started near the optimum (the selection refined every parameter on a fine grid): a first trust radius
  // of 10 % and a tolerance of 0.1 % in tau - an offset of 0.1 % changes the RSS by (0.001 / sd)^2 whitened
  // units, below 0.01 in dBIC for any parameter known to better than 1 %.
  const Projected p = optimise_parameters(in, yw, model, taus, sc, w, log_tau, {30, 1e-3, 0.1});
  return {p.rss, static_cast<int>(taus.size()), at_parameters(model, taus, log_tau), p.converged};
}

RefitResult refit(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& model, bool refine_lag, const TermScaling& sc,
                  const Whitener& w, bool optimised) {
  RefitResult out;
  const Eigen::VectorXd yw = w.apply(y);
  out.nonlinear = nonlinear_parameters(model, refine_lag);
  std::vector<double> log_tau;
  for (const auto& t : out.nonlinear) log_tau.push_back(std::log(t.value));
  if (!optimised) optimise_parameters(in, yw, model, out.nonlinear, sc, w, log_tau);
  out.model = at_parameters(model, out.nonlinear, log_tau);

  // Linear coefficients at the optimum; dependent columns are dropped before the joint problem.
  const Eigen::MatrixXd x0 = w.apply(model_columns(out.model, in.signals, sc));
  const WhitenedFit start = fit_whitened(x0, yw);
  out.kept = start.kept;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index c = 0; c < x0.cols(); ++c) {
    if (start.kept[static_cast<std::size_t>(c)]) kept.push_back(c);
  }
  // The kept coefficients, then each log tau, in one buffer in that order: Ceres orders the Jacobian's and
  // the covariance's columns by the blocks' addresses, which must not follow the heap's layout.
  std::vector<double> parameters(kept.size() + log_tau.size());
  for (std::size_t c = 0; c < kept.size(); ++c) parameters[c] = start.beta(kept[c]);
  std::copy(log_tau.begin(), log_tau.end(), parameters.begin() + static_cast<std::ptrdiff_t>(kept.size()));
  const double* beta = parameters.data();

  ceres::Problem problem;
  std::vector<double*> blocks{parameters.data()};
  for (std::size_t k = 0; k < log_tau.size(); ++k) blocks.push_back(parameters.data() + kept.size() + k);
  if (!kept.empty()) problem.AddResidualBlock(new RefitCost(in, yw, model, out.nonlinear, kept, sc, w), nullptr, blocks);
  const ceres::Solver::Summary summary = kept.empty() ? ceres::Solver::Summary() : polish(problem);
  std::copy(parameters.begin() + static_cast<std::ptrdiff_t>(kept.size()), parameters.end(), log_tau.begin());
  out.termination = kept.empty() ? "no parameters" : ceres::TerminationTypeToString(summary.termination_type);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.model = at_parameters(model, out.nonlinear, log_tau);
  for (std::size_t k = 0; k < out.nonlinear.size(); ++k) out.nonlinear[k].value = std::exp(log_tau[k]);

  out.beta = Eigen::VectorXd::Zero(x0.cols());
  out.beta_sigma = Eigen::VectorXd::Zero(x0.cols());
  for (std::size_t c = 0; c < kept.size(); ++c) out.beta(kept[c]) = beta[c];
  const double dof = std::max(1.0, static_cast<double>(yw.size()) - static_cast<double>(kept.size() + log_tau.size()));
  const double sigma2 = kept.empty() ? yw.squaredNorm() / dof : 2.0 * summary.final_cost / dof;
  out.residual_sigma = std::sqrt(sigma2);
  if (!kept.empty()) intervals(problem, blocks, kept, sigma2, out);
  return out;
}

}  // namespace gyrosid::explain
