#include "solvers/lrols_loo/lrols_loo_solver.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "solvers/common/candidates.h"
#include "solvers/common/recursive_loo.h"

namespace gyrosid {

OptionTable LrolsLooOptions::table() {
  OptionTable t("lrols_loo");
  t.real("width", &width, 0.0, 1e6, "node width in normalised input units", true)
      .text("widths", &widths, "per-input widths, comma-separated (overrides width)")
      .integer("candidates", &candidates, 0, 1000000, "candidate centres (space-filling subset; 0 = all points)")
      .integer("max_nodes", &max_nodes, 1, 100000, "upper bound on the number of nodes")
      .real("lambda", &lambda, 0.0, 1e6, "initial local ridge parameter of every weight")
      .integer("passes", &passes, 1, 50, "selection passes with evidence updates of the lambdas");
  return t;
}

std::string LrolsLooOptions::validate() const { return check_positive_list(widths, "widths"); }

namespace {

struct Selection {
  std::vector<Eigen::Index> nodes;  // candidate indices, in order
  Eigen::VectorXd d, g, qy;         // per selected node: |w|^2, weight, w'y
  Eigen::MatrixXd r_tilde;          // H_sel = W_unit r_tilde (unit orthogonal columns)
  std::vector<double> loo_history;
  double loo = 0.0;
  double rss = 0.0;
  std::string stop_reason;
};

// One forward-selection pass with fixed per-candidate lambdas. h: N x M candidate matrix.
Selection select_pass(const Eigen::MatrixXd& h, const Eigen::VectorXd& y, const Eigen::VectorXd& lambda, int max_nodes) {
  const Eigen::Index n = h.rows(), m = h.cols();
  Eigen::MatrixXd w = h;  // candidates, orthogonalised against the selected set as it grows
  RecursiveLoo loo(y);
  std::vector<bool> alive(static_cast<std::size_t>(m), true);
  const Eigen::VectorXd norm2 = h.colwise().squaredNorm().transpose();
  const int cap = std::min<int>(max_nodes, static_cast<int>(m));
  Selection s;
  s.d.resize(cap), s.g.resize(cap), s.qy.resize(cap);
  s.r_tilde = Eigen::MatrixXd::Zero(cap, cap);
  Eigen::MatrixXd q(n, cap);
  double current = loo.mse();  // LOO of the empty model
  s.stop_reason = "max_nodes";
  Eigen::VectorXd score(m);
  while (static_cast<int>(s.nodes.size()) < cap) {
    // LOO after adding each live candidate.
    parallel_for(m, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
      for (Eigen::Index j = begin; j < end; ++j) {
        score(j) = std::numeric_limits<double>::infinity();
        if (!alive[static_cast<std::size_t>(j)]) continue;
        if (!(w.col(j).squaredNorm() > 1e-9 * norm2(j))) continue;
        score(j) = loo.mse_after(w.col(j), y, lambda(j));
      }
    }, 16);
    Eigen::Index pick = -1;
    double best = current;
    for (Eigen::Index j = 0; j < m; ++j) {
      if (score(j) < best) best = score(j), pick = j;
    }
    if (pick < 0) {
      s.stop_reason = "loo_minimum";
      break;
    }
    const Eigen::Index k = static_cast<Eigen::Index>(s.nodes.size());
    const double dk = w.col(pick).squaredNorm();
    const double sk = std::sqrt(dk);
    q.col(k) = w.col(pick) / sk;
    // Coefficients of the chosen raw column on the unit vectors (re-orthogonalised for stability).
    Eigen::VectorXd coeff = q.leftCols(k).transpose() * h.col(pick);
    s.r_tilde.col(k).head(k) = coeff;
    s.r_tilde(k, k) = sk;
    s.d(k) = dk;
    s.qy(k) = w.col(pick).dot(y);
    s.g(k) = loo.add(w.col(pick), y, lambda(pick));  // weight on the unnormalised w_k
    s.nodes.push_back(pick);
    s.loo_history.push_back(best);
    current = best;
    alive[static_cast<std::size_t>(pick)] = false;
    // Orthogonalise every live candidate against the new unit vector (modified Gram-Schmidt, rank one).
    const auto qk = q.col(k);
    parallel_for(m, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
      const Eigen::Index len = end - begin;
      const Eigen::RowVectorXd c = qk.transpose() * w.middleCols(begin, len);
      w.middleCols(begin, len).noalias() -= qk * c;
    }, 16);
  }
  const Eigen::Index kk = static_cast<Eigen::Index>(s.nodes.size());
  s.d.conservativeResize(kk), s.g.conservativeResize(kk), s.qy.conservativeResize(kk);
  s.r_tilde.conservativeResize(kk, kk);
  s.loo = current;
  s.rss = loo.residuals().squaredNorm();
  return s;
}

}  // namespace

SolveOutcome LrolsLooSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const Eigen::Index n = problem.size(), dim = problem.dimension();
  const Eigen::RowVectorXd r = node_widths(o_.width, parse_list(o_.widths, "lrols_loo option 'widths'"), dim);
  const std::vector<Eigen::Index> cand = select_candidates(problem.x, o_.candidates);
  const Eigen::Index m = static_cast<Eigen::Index>(cand.size());
  const Eigen::MatrixXd h = gaussian_columns(problem.x, rows_of(problem.x, cand), r);

  Eigen::VectorXd lambda = Eigen::VectorXd::Constant(m, o_.lambda);
  Selection s;
  std::vector<Eigen::Index> previous;
  int pass = 0;
  bool settled = false;
  for (; pass < o_.passes; ++pass) {
    s = select_pass(h, problem.y, lambda, o_.max_nodes);
    if (s.nodes.empty()) fail("lrols_loo: no node lowers the leave-one-out error (target constant or zero?)");
    monitor.iteration(s.loo);
    // Evidence update of the selected lambdas (the others keep theirs).
    const Eigen::VectorXd a = s.d + Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(s.d.size(), [&](Eigen::Index k) {
                                return lambda(s.nodes[static_cast<std::size_t>(k)]);
                              }));
    const Eigen::VectorXd gamma_k = s.d.cwiseQuotient(a);
    const double gamma = gamma_k.sum();
    for (Eigen::Index k = 0; k < s.d.size(); ++k) {
      const double g2 = s.g(k) * s.g(k);
      if (g2 > 0) {
        lambda(s.nodes[static_cast<std::size_t>(k)]) =
            std::clamp(gamma_k(k) / std::max(static_cast<double>(n) - gamma, 1.0) * s.rss / g2, 1e-14, 1e6);
      }
    }
    if (s.nodes == previous) {
      settled = true;
      ++pass;
      break;
    }
    previous = s.nodes;
  }
  // Weights of the raw columns: H_sel a = W g = Q (s .* g)  =>  r_tilde a = sqrt(d) .* g.
  const Eigen::VectorXd t = s.d.cwiseSqrt().cwiseProduct(s.g);
  const Eigen::Index k = s.d.size();
  net.weights = s.r_tilde.triangularView<Eigen::Upper>().solve(t);
  net.centres.resize(k, dim);
  for (Eigen::Index i = 0; i < k; ++i) net.centres.row(i) = problem.x.row(cand[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(i)])]);
  net.widths = r.replicate(k, 1);
  net.bias = 0.0;

  std::vector<double> used;
  for (Eigen::Index i = 0; i < k; ++i) used.push_back(lambda(s.nodes[static_cast<std::size_t>(i)]));
  // Converged when the selected set stopped changing and the last pass stopped at its LOO minimum.
  const bool converged = settled && s.stop_reason == "loo_minimum";
  return {converged ? Termination::converged : Termination::iteration_limit,
          (settled ? "selection settled after " : "passes exhausted after ") + std::to_string(pass) + " passes; last pass: " + s.stop_reason,
          {{"loo", s.loo}, {"loo_history", s.loo_history}, {"rss", s.rss}, {"candidates", m}, {"lambdas", used}}};
}

}  // namespace gyrosid
