#include "solvers/ofs_loo/ofs_loo_solver.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

#include "core/bounded_search.h"
#include "core/error.h"
#include "core/parallel.h"
#include "model/gaussian_node.h"
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

namespace {

struct TunedNode {
  Eigen::VectorXd centre, widths;
  double loo = INFINITY;
};

// One stage's node: the candidate centre with the lowest LOO at the starting width, then its centre and
// log widths tuned by BOBYQA within the data range (plus a margin) and the width bounds.
TunedNode tune_node(const RbfProblem& problem, const OrthogonalModel& model, const std::vector<Eigen::Index>& cand,
                    const OfsLooOptions& o, SolveMonitor& monitor) {
  const Eigen::Index dim = problem.dimension(), m = static_cast<Eigen::Index>(cand.size());
  const Eigen::RowVectorXd lo = problem.x.colwise().minCoeff(), hi = problem.x.colwise().maxCoeff();
  const std::vector<double> default_r(static_cast<std::size_t>(dim), o.width);
  Eigen::VectorXd screen(m);
  parallel_for(m, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
    for (Eigen::Index j = b; j < e; ++j) {
      const Eigen::RowVectorXd c = problem.x.row(cand[static_cast<std::size_t>(j)]);
      screen(j) = model.trial(node_column(problem.x, c.data(), default_r.data()), problem.y);
    }
  }, 4);
  Eigen::Index best_j = 0;
  screen.minCoeff(&best_j);
  // Parameters [c_1..c_d, log r_1..log r_d].
  // The node's [c, rho] (a NodeBlock without its weight, which the trial solves for).
  std::vector<double> p(static_cast<std::size_t>(2 * dim)), lb(p.size()), ub(p.size());
  const NodeBlock<double> start{p.data(), dim}, lower{lb.data(), dim}, upper{ub.data(), dim};
  for (Eigen::Index k = 0; k < dim; ++k) {
    const double margin = 0.1 * (hi(k) - lo(k));
    start.centre()[k] = problem.x(cand[static_cast<std::size_t>(best_j)], k), lower.centre()[k] = lo(k) - margin, upper.centre()[k] = hi(k) + margin;
    start.log_width()[k] = std::log(o.width), lower.log_width()[k] = std::log(o.min_width), upper.log_width()[k] = std::log(o.max_width);
  }
  auto unpack = [dim](const std::vector<double>& v, Eigen::VectorXd& c, Eigen::VectorXd& r) {
    const NodeBlock<const double> node{v.data(), dim};
    c.resize(dim), r.resize(dim);
    for (Eigen::Index k = 0; k < dim; ++k) c(k) = node.centre()[k], r(k) = std::exp(node.log_width()[k]);  // std::exp: Eigen's differs in the last bit
  };
  const std::function<double(const std::vector<double>&)> loo = [&](const std::vector<double>& v) {
    Eigen::VectorXd c, r;
    unpack(v, c, r);
    monitor.evaluation();
    return model.trial(node_column(problem.x, c.data(), r.data()), problem.y);
  };
  BoundedSearchOptions search;
  search.max_evaluations = o.evaluations, search.xtol_rel = 1e-6;
  p = minimize_bounded(loo, p, lb, ub, search).x;
  TunedNode node;
  node.loo = loo(p);
  unpack(p, node.centre, node.widths);
  return node;
}

}  // namespace

SolveOutcome OfsLooSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const OfsLooOptions& o = o_;
  const Eigen::Index n = problem.size(), dim = problem.dimension();
  const std::vector<Eigen::Index> cand = select_candidates(problem.x, o.candidates);
  OrthogonalModel model{Eigen::MatrixXd(n, o.max_nodes), 0, RecursiveLoo(problem.y), o.lambda};
  double current = model.loo.mse();
  std::vector<TunedNode> nodes;
  Eigen::MatrixXd r_tilde = Eigen::MatrixXd::Zero(o.max_nodes, o.max_nodes);  // Phi = Q r_tilde
  Eigen::VectorXd t(o.max_nodes);  // fitted = Q t: t_k = |w_k| g_k
  bool at_minimum = false;
  while (static_cast<int>(nodes.size()) < o.max_nodes) {
    TunedNode node = tune_node(problem, model, cand, o, monitor);
    if (!(node.loo < current * (1.0 - 1e-9))) {
      at_minimum = true;
      break;
    }
    const Eigen::VectorXd phi = node_column(problem.x, node.centre.data(), node.widths.data());
    const Eigen::VectorXd w = model.orthogonalise(phi);
    const double d = w.squaredNorm(), g = model.loo.add(w, problem.y, model.lambda);
    const Eigen::Index kk = model.k;
    r_tilde.col(kk).head(kk) = model.q.leftCols(kk).transpose() * phi;
    r_tilde(kk, kk) = std::sqrt(d);
    t(kk) = std::sqrt(d) * g;
    model.q.col(model.k++) = w / std::sqrt(d);
    current = node.loo;
    monitor.iteration(current);
    nodes.push_back(std::move(node));
  }
  if (nodes.empty()) fail("ofs_loo: no node lowers the leave-one-out error");

  // Weights of the raw Gaussian columns: Phi a = Q t  =>  r_tilde a = t (upper triangular).
  const Eigen::Index k = static_cast<Eigen::Index>(nodes.size());
  net.weights = r_tilde.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(t.head(k));
  net.centres.resize(k, dim);
  net.widths.resize(k, dim);
  for (Eigen::Index j = 0; j < k; ++j) {
    net.centres.row(j) = nodes[static_cast<std::size_t>(j)].centre.transpose();
    net.widths.row(j) = nodes[static_cast<std::size_t>(j)].widths.transpose();
  }
  net.bias = 0.0;
  return {at_minimum ? Termination::converged : Termination::iteration_limit,
          at_minimum ? "leave-one-out minimum" : "max_nodes reached", {{"loo", current}, {"candidates", cand.size()}}};
}

}  // namespace gyrosid
