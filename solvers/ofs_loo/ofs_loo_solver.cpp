#include "solvers/ofs_loo/ofs_loo_solver.h"

#include <Eigen/Dense>
#include <nlopt.hpp>

#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "solvers/common/candidates.h"

namespace gyrosid {

OptionTable OfsLooOptions::table() {
  OptionTable t("ofs_loo");
  t.real("width", &width, 0.0, 1e6, "starting node width (normalised units)", true)
      .real("min_width", &min_width, 0.0, 1e6, "lower bound of tuned widths", true)
      .real("max_width", &max_width, 0.0, 1e6, "upper bound of tuned widths", true)
      .integer("candidates", &candidates, 1, 100000, "centres screened for each stage's starting point")
      .integer("max_nodes", &max_nodes, 1, 10000, "upper bound on the number of nodes")
      .integer("evaluations", &evaluations, 10, 100000, "BOBYQA evaluations per node")
      .real("lambda", &lambda, 0.0, 1e6, "ridge parameter of every orthogonal weight");
  return t;
}

OfsLooSolver::OfsLooSolver(const OptionMap& options) {
  options_.table().apply(options);
  if (!(options_.min_width < options_.max_width)) fail("ofs_loo: min_width must be below max_width");
  if (options_.width < options_.min_width || options_.width > options_.max_width) {
    fail("ofs_loo option 'width' = ", options_.width, " is outside [min_width, max_width]");
  }
}

std::string OfsLooSolver::help() {
  OfsLooOptions o;
  return "ofs_loo - orthogonal forward selection with tuned centres and widths, LOO criterion (Chen et al. 2009):\n" +
         o.table().help();
}

namespace {

// The growing orthogonal model: unit columns Q, residual e, LOO denominators eta.
struct OrthogonalModel {
  Eigen::MatrixXd q;
  Eigen::Index k = 0;
  Eigen::VectorXd e, eta;
  double lambda = 0;

  // Orthogonalised column of phi (twice, for stability) and the LOO after adding it.
  double trial(const Eigen::VectorXd& phi, const Eigen::VectorXd& y, Eigen::VectorXd* w_out) const {
    Eigen::VectorXd w = phi;
    for (int pass = 0; pass < 2 && k > 0; ++pass) w -= q.leftCols(k) * (q.leftCols(k).transpose() * w);
    const double d = w.squaredNorm();
    if (!(d > 1e-10 * phi.squaredNorm())) return std::numeric_limits<double>::infinity();
    const double a = d + lambda, g = w.dot(y) / a;
    const double loo = ((e - g * w).array() / (eta - w.cwiseAbs2() / a).array().max(1e-12)).square().mean();
    if (w_out) *w_out = std::move(w);
    return loo;
  }
};

Eigen::VectorXd node_column(const Eigen::MatrixXd& x, const double* c, const double* r) {
  const Eigen::Index n = x.rows(), d = x.cols();
  Eigen::VectorXd phi(n);
  std::vector<double> row(static_cast<std::size_t>(d));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index k = 0; k < d; ++k) row[static_cast<std::size_t>(k)] = x(i, k);
    phi(i) = gaussian(row.data(), c, r, d, 1);
  }
  return phi;
}

}  // namespace

SolverSummary OfsLooSolver::train(const RbfProblem& problem, RbfNetwork& net) {
  const auto start = std::chrono::steady_clock::now();
  const OfsLooOptions& o = options_;
  const Eigen::Index n = problem.size(), dim = problem.dimension();
  const Eigen::VectorXd& y = problem.y;
  const std::vector<Eigen::Index> cand = select_candidates(problem.x, o.candidates);
  const Eigen::Index m = static_cast<Eigen::Index>(cand.size());
  const Eigen::RowVectorXd lo = problem.x.colwise().minCoeff(), hi = problem.x.colwise().maxCoeff();

  OrthogonalModel model;
  model.q.resize(n, o.max_nodes);
  model.e = y;
  model.eta = Eigen::VectorXd::Ones(n);
  model.lambda = o.lambda;
  double current = y.squaredNorm() / static_cast<double>(n);

  std::vector<Eigen::VectorXd> centres, widths;
  Eigen::MatrixXd r_tilde = Eigen::MatrixXd::Zero(o.max_nodes, o.max_nodes);  // Phi = Q r_tilde
  Eigen::VectorXd t(o.max_nodes);  // fitted = Q t: t_k = |w_k| g_k
  std::vector<double> history;
  std::string termination = "max_nodes";
  int total_evaluations = 0;
  const std::vector<double> default_r(static_cast<std::size_t>(dim), o.width);

  while (static_cast<int>(centres.size()) < o.max_nodes) {
    // Screening: every candidate centre at the default width.
    Eigen::VectorXd screen(m);
    parallel_for(m, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      std::vector<double> c(static_cast<std::size_t>(dim));
      for (Eigen::Index j = b; j < e; ++j) {
        for (Eigen::Index k = 0; k < dim; ++k) c[static_cast<std::size_t>(k)] = problem.x(cand[static_cast<std::size_t>(j)], k);
        screen(j) = model.trial(node_column(problem.x, c.data(), default_r.data()), y, nullptr);
      }
    }, 4);
    Eigen::Index best_j = 0;
    screen.minCoeff(&best_j);
    // Local tuning of (centre, log widths) by BOBYQA.
    std::vector<double> p(static_cast<std::size_t>(2 * dim)), lb(p.size()), ub(p.size());
    for (Eigen::Index k = 0; k < dim; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      p[kk] = problem.x(cand[static_cast<std::size_t>(best_j)], k);
      const double margin = 0.1 * (hi(k) - lo(k));
      lb[kk] = lo(k) - margin, ub[kk] = hi(k) + margin;
      p[kk + static_cast<std::size_t>(dim)] = std::log(o.width);
      lb[kk + static_cast<std::size_t>(dim)] = std::log(o.min_width), ub[kk + static_cast<std::size_t>(dim)] = std::log(o.max_width);
    }
    std::function<double(const std::vector<double>&)> f = [&](const std::vector<double>& v) {
      std::vector<double> r(static_cast<std::size_t>(dim));
      for (Eigen::Index k = 0; k < dim; ++k) r[static_cast<std::size_t>(k)] = std::exp(v[static_cast<std::size_t>(k + dim)]);
      ++total_evaluations;
      return model.trial(node_column(problem.x, v.data(), r.data()), y, nullptr);
    };
    nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(2 * dim));
    opt.set_lower_bounds(lb);
    opt.set_upper_bounds(ub);
    opt.set_maxeval(o.evaluations);
    opt.set_xtol_rel(1e-6);
    opt.set_min_objective([](const std::vector<double>& v, std::vector<double>&, void* data) {
      return (*static_cast<std::function<double(const std::vector<double>&)>*>(data))(v);
    }, &f);
    double value = screen(best_j);
    try {
      opt.optimize(p, value);
    } catch (const std::exception&) {
      // BOBYQA stops on roundoff with its best point in p.
    }
    value = f(p);
    if (!(value < current * (1.0 - 1e-9))) {
      termination = "loo_minimum";
      break;
    }
    Eigen::VectorXd c(dim), r(dim);
    for (Eigen::Index k = 0; k < dim; ++k) c(k) = p[static_cast<std::size_t>(k)], r(k) = std::exp(p[static_cast<std::size_t>(k + dim)]);
    Eigen::VectorXd phi = node_column(problem.x, c.data(), r.data());
    Eigen::VectorXd w;
    model.trial(phi, y, &w);
    const double d = w.squaredNorm(), a = d + model.lambda, g = w.dot(y) / a;
    const Eigen::Index kk = model.k;
    r_tilde.col(kk).head(kk) = model.q.leftCols(kk).transpose() * phi;
    r_tilde(kk, kk) = std::sqrt(d);
    t(kk) = std::sqrt(d) * g;
    model.e -= g * w;
    model.eta -= w.cwiseAbs2() / a;
    model.q.col(model.k++) = w / std::sqrt(d);
    current = value;
    history.push_back(value);
    centres.push_back(c);
    widths.push_back(r);
  }
  if (centres.empty()) fail("ofs_loo: no node lowers the leave-one-out error");

  // Weights of the raw Gaussian columns: Phi a = Q t  =>  r_tilde a = t (upper triangular).
  const Eigen::Index k = static_cast<Eigen::Index>(centres.size());
  net.weights = r_tilde.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(t.head(k));
  net.centres.resize(k, dim);
  net.widths.resize(k, dim);
  for (Eigen::Index j = 0; j < k; ++j) {
    net.centres.row(j) = centres[static_cast<std::size_t>(j)].transpose();
    net.widths.row(j) = widths[static_cast<std::size_t>(j)].transpose();
  }
  net.bias = 0.0;

  SolverSummary s;
  s.solver = "ofs_loo";
  s.termination = termination;
  s.iterations = static_cast<int>(k);
  s.cost_history = history;
  s.nodes = static_cast<int>(k);
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.peak_rss_mb = peak_rss_mb();
  s.details = {{"loo", current}, {"evaluations", total_evaluations}, {"candidates", m}};
  return s;
}

}  // namespace gyrosid
