#include "solvers/ofs_loo/ofs_loo_solver.h"

#include <Eigen/Dense>
#include <nlopt.hpp>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "solvers/common/candidates.h"
#include "solvers/common/recursive_loo.h"

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

std::string OfsLooOptions::validate() const {
  if (!(min_width < max_width)) return "min_width must be below max_width";
  if (width < min_width || width > max_width) return str_cat("option 'width' = ", width, " is outside [min_width, max_width]");
  return "";
}

namespace {

// The growing orthogonal model: unit columns Q (k of them) and the recursive LOO state.
struct OrthogonalModel {
  Eigen::MatrixXd q;
  Eigen::Index k = 0;
  RecursiveLoo loo;
  double lambda = 0;

  // phi orthogonalised against Q (twice, for stability); empty when phi lies in the span of Q.
  Eigen::VectorXd orthogonalise(const Eigen::VectorXd& phi) const {
    Eigen::VectorXd w = phi;
    for (int pass = 0; pass < 2 && k > 0; ++pass) w -= q.leftCols(k) * (q.leftCols(k).transpose() * w);
    if (!(w.squaredNorm() > 1e-10 * phi.squaredNorm())) return {};
    return w;
  }
  // The LOO error after adding phi.
  double trial(const Eigen::VectorXd& phi, const Eigen::VectorXd& y) const {
    const Eigen::VectorXd w = orthogonalise(phi);
    return w.size() == 0 ? std::numeric_limits<double>::infinity() : loo.mse_after(w, y, lambda);
  }
};

// The Gaussian column of one node with centre c and widths r (d values each).
Eigen::VectorXd node_column(const Eigen::MatrixXd& x, const double* c, const double* r) {
  const Eigen::Index d = x.cols();
  const Eigen::MatrixXd centre = Eigen::Map<const Eigen::RowVectorXd>(c, d), widths = Eigen::Map<const Eigen::RowVectorXd>(r, d);
  return gaussian_columns(x, centre, widths);
}

}  // namespace

SolveOutcome OfsLooSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const OfsLooOptions& o = options_;
  const Eigen::Index n = problem.size(), dim = problem.dimension();
  const Eigen::VectorXd& y = problem.y;
  const std::vector<Eigen::Index> cand = select_candidates(problem.x, o.candidates);
  const Eigen::Index m = static_cast<Eigen::Index>(cand.size());
  const Eigen::RowVectorXd lo = problem.x.colwise().minCoeff(), hi = problem.x.colwise().maxCoeff();

  OrthogonalModel model{Eigen::MatrixXd(n, o.max_nodes), 0, RecursiveLoo(y), o.lambda};
  double current = model.loo.mse();

  std::vector<Eigen::VectorXd> centres, widths;
  Eigen::MatrixXd r_tilde = Eigen::MatrixXd::Zero(o.max_nodes, o.max_nodes);  // Phi = Q r_tilde
  Eigen::VectorXd t(o.max_nodes);  // fitted = Q t: t_k = |w_k| g_k
  bool at_minimum = false;
  const std::vector<double> default_r(static_cast<std::size_t>(dim), o.width);

  while (static_cast<int>(centres.size()) < o.max_nodes) {
    // Screening: every candidate centre at the default width.
    Eigen::VectorXd screen(m);
    parallel_for(m, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      std::vector<double> c(static_cast<std::size_t>(dim));
      for (Eigen::Index j = b; j < e; ++j) {
        for (Eigen::Index k = 0; k < dim; ++k) c[static_cast<std::size_t>(k)] = problem.x(cand[static_cast<std::size_t>(j)], k);
        screen(j) = model.trial(node_column(problem.x, c.data(), default_r.data()), y);
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
      monitor.evaluation();
      return model.trial(node_column(problem.x, v.data(), r.data()), y);
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
      at_minimum = true;
      break;
    }
    Eigen::VectorXd c(dim), r(dim);
    for (Eigen::Index k = 0; k < dim; ++k) c(k) = p[static_cast<std::size_t>(k)], r(k) = std::exp(p[static_cast<std::size_t>(k + dim)]);
    Eigen::VectorXd phi = node_column(problem.x, c.data(), r.data());
    const Eigen::VectorXd w = model.orthogonalise(phi);
    const double d = w.squaredNorm(), g = model.loo.add(w, y, model.lambda);
    const Eigen::Index kk = model.k;
    r_tilde.col(kk).head(kk) = model.q.leftCols(kk).transpose() * phi;
    r_tilde(kk, kk) = std::sqrt(d);
    t(kk) = std::sqrt(d) * g;
    model.q.col(model.k++) = w / std::sqrt(d);
    current = value;
    monitor.iteration(value);
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

  return {at_minimum ? Termination::converged : Termination::iteration_limit,
          at_minimum ? "leave-one-out minimum" : "max_nodes reached", {{"loo", current}, {"candidates", m}}};
}

}  // namespace gyrosid
