#include "solvers/ols/forward_selection.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "model/rbf_network.h"
#include "solvers/common/candidates.h"

namespace gyrosid {

double selection_criterion(SelectionCriterion criterion, double rss, double gamma, double n) {
  const double dof = std::max(n - gamma, 1e-12);
  switch (criterion) {
    case SelectionCriterion::uev: return rss / dof;
    case SelectionCriterion::fpe: return rss * (n + gamma) / (n * dof);
    case SelectionCriterion::gcv: return n * rss / (dof * dof);
    case SelectionCriterion::bic: return rss * (n + (std::log(n) - 1.0) * gamma) / (n * dof);
    case SelectionCriterion::loo: break;
  }
  fail("selection_criterion: LOO needs the residuals");
}

namespace {

// Regularised quantities of the orthogonal model for a given lambda (d: squared norms, qy: projections of y
// on the unit columns, r2: |unregularised residual|^2).
struct RidgeState {
  double rss = 0, gamma = 0, sum_d_over_a2 = 0, sum_g2_over_a = 0;
};

RidgeState ridge_state(const Eigen::VectorXd& d, const Eigen::VectorXd& qy, Eigen::Index k, double r2, double lambda) {
  RidgeState s;
  s.rss = r2;
  for (Eigen::Index i = 0; i < k; ++i) {
    const double a = d(i) + lambda;
    const double shrink = qy(i) * lambda / a;  // e = r + sum_k q_k qy_k lambda/(d_k + lambda)
    s.rss += shrink * shrink;
    s.gamma += d(i) / a;
    s.sum_d_over_a2 += d(i) / (a * a);
    const double g = std::sqrt(d(i)) * qy(i) / a;  // g_k = c_k/(d_k + lambda), c_k = s_k qy_k
    s.sum_g2_over_a += g * g / a;
  }
  return s;
}

// The candidate columns H (N x M) and, per live column, its squared norm, its correlation with the
// unregularised residual and its coefficients on the selected unit vectors (coef = Q'H, one row per selected
// node), whose squared column norms give each candidate's projection on the selected span. Columns of
// selected or collinear candidates are compacted away once a quarter of the matrix is dead.
struct CandidatePool {
  Eigen::MatrixXd h, coef;
  Eigen::VectorXd norm2, proj2, corr;
  std::vector<bool> alive;
  std::vector<Eigen::Index> candidate_of;  // column -> candidate index
  Eigen::Index live = 0;

  CandidatePool(Eigen::MatrixXd columns, const Eigen::VectorXd& y, int cap) : h(std::move(columns)) {
    const Eigen::Index m = h.cols();
    norm2 = h.colwise().squaredNorm().transpose();
    proj2 = Eigen::VectorXd::Zero(m);
    corr = h.transpose() * y;
    coef.resize(cap, m);
    alive.assign(static_cast<std::size_t>(m), true);
    candidate_of.resize(static_cast<std::size_t>(m));
    for (Eigen::Index j = 0; j < m; ++j) candidate_of[static_cast<std::size_t>(j)] = j;
    live = m;
  }

  void kill(Eigen::Index j) {
    alive[static_cast<std::size_t>(j)] = false;
    --live;
  }

  void compact_if_sparse() {
    if (!(4 * live < 3 * h.cols())) return;
    Eigen::Index out = 0;
    for (Eigen::Index j = 0; j < h.cols(); ++j) {
      if (!alive[static_cast<std::size_t>(j)]) continue;
      if (out != j) {
        h.col(out) = h.col(j);
        coef.col(out) = coef.col(j);
        norm2(out) = norm2(j), proj2(out) = proj2(j), corr(out) = corr(j);
        candidate_of[static_cast<std::size_t>(out)] = candidate_of[static_cast<std::size_t>(j)];
      }
      ++out;
    }
    h.conservativeResize(Eigen::NoChange, out);
    coef.conservativeResize(Eigen::NoChange, out);
    norm2.conservativeResize(out), proj2.conservativeResize(out), corr.conservativeResize(out);
    candidate_of.resize(static_cast<std::size_t>(out));
    alive.assign(static_cast<std::size_t>(out), true);
    live = out;
  }

  // The live column with the largest regularised cost reduction corr^2 / (remainder + lambda); columns whose
  // orthogonal remainder is below the collinearity tolerance are dropped on the way. -1 when none is left.
  Eigen::Index pick(double lambda, double collinear_tolerance, int& skipped) {
    Eigen::Index best = -1;
    double best_score = -1.0;
    for (Eigen::Index j = 0; j < h.cols(); ++j) {
      if (!alive[static_cast<std::size_t>(j)]) continue;
      const double rem = norm2(j) - proj2(j);
      if (!(rem > collinear_tolerance * norm2(j))) {
        kill(j);
        ++skipped;
        continue;
      }
      const double score = corr(j) * corr(j) / (rem + lambda);
      if (score > best_score) best_score = score, best = j;
    }
    return best;
  }

  // Row k of Q'H for every live candidate after unit vector q_k: the one O(N M) product per step.
  void absorb(Eigen::Index k, const Eigen::Ref<const Eigen::VectorXd>& qk, double qy_k) {
    parallel_for(h.cols(), [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
      const Eigen::Index len = end - begin;
      coef.row(k).segment(begin, len).noalias() = qk.transpose() * h.middleCols(begin, len);
      proj2.segment(begin, len) += coef.row(k).segment(begin, len).transpose().cwiseAbs2();
      corr.segment(begin, len) -= qy_k * coef.row(k).segment(begin, len).transpose();
    }, 64);
  }
};

// The selected orthogonal model: unit columns Q, H_selected = Q r_tilde, squared norms d and projections qy
// of y on the unit columns, the unregularised residual.
struct OrthogonalSet {
  Eigen::MatrixXd q, r_tilde;
  Eigen::VectorXd qy, d, r_ols;
  Eigen::Index k = 0;
  OrthogonalSet(Eigen::Index n, int cap, const Eigen::VectorXd& y)
      : q(n, cap), r_tilde(Eigen::MatrixXd::Zero(cap, cap)), qy(cap), d(cap), r_ols(y) {}

  // Orthogonalises column h (with its stored coefficients on Q), classical Gram-Schmidt then one full
  // re-orthogonalisation pass ("twice is enough": as stable as modified Gram-Schmidt). False when the
  // remainder is collinear.
  bool add(const Eigen::Ref<const Eigen::VectorXd>& h, Eigen::VectorXd coeff, double norm2, double collinear_tolerance) {
    Eigen::VectorXd v = h - q.leftCols(k) * coeff;
    const Eigen::VectorXd again = q.leftCols(k).transpose() * v;
    v -= q.leftCols(k) * again;
    coeff += again;
    const double dk = v.squaredNorm();
    if (!(dk > collinear_tolerance * norm2)) return false;
    const double sk = std::sqrt(dk);
    q.col(k) = v / sk;
    r_tilde.col(k).head(k) = coeff;
    r_tilde(k, k) = sk;
    d(k) = dk;
    qy(k) = q.col(k).dot(r_ols);
    r_ols -= qy(k) * q.col(k);
    ++k;
    return true;
  }

  // Orr's GCV fixed point for the global ridge parameter, from `lambda`.
  double reestimate_lambda(double lambda, double n) const {
    const double r2 = r_ols.squaredNorm();
    for (int it = 0; it < 30; ++it) {
      const RidgeState s = ridge_state(d, qy, k, r2, lambda);
      if (!(s.sum_g2_over_a > 0) || !(s.sum_d_over_a2 > 0)) break;
      const double next = std::clamp(s.rss * s.sum_d_over_a2 / (std::max(n - s.gamma, 1e-12) * s.sum_g2_over_a), 1e-14, 1e6);
      const bool done = std::abs(next - lambda) <= 1e-6 * lambda;
      lambda = next;
      if (done) break;
    }
    return lambda;
  }

  // The model-selection criterion of the current k-node model.
  double criterion(SelectionCriterion c, double lambda) const {
    const double n = static_cast<double>(r_ols.size());
    if (c != SelectionCriterion::loo) {
      const RidgeState s = ridge_state(d, qy, k, r_ols.squaredNorm(), lambda);
      return selection_criterion(c, s.rss, s.gamma, n);
    }
    // e = r + Q b, 1 - h_ii = 1 - (Q.^2) a, with a_k = d_k/(d_k + lambda), b_k = qy_k lambda/(d_k + lambda).
    Eigen::VectorXd a(k), b(k);
    for (Eigen::Index i = 0; i < k; ++i) {
      a(i) = d(i) / (d(i) + lambda);
      b(i) = qy(i) * lambda / (d(i) + lambda);
    }
    const Eigen::VectorXd e = r_ols + q.leftCols(k) * b;
    const Eigen::VectorXd eta = Eigen::VectorXd::Ones(r_ols.size()) - q.leftCols(k).cwiseAbs2() * a;
    return (e.array() / eta.array().max(1e-12)).square().mean();
  }
};

}  // namespace

ForwardSelectionResult forward_select(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const ForwardSelectionOptions& o) {
  const Eigen::Index n = x.rows(), dim = x.cols();
  if (n == 0) fail("forward selection: no training samples");
  if (o.widths.size() != dim) fail("forward selection: ", o.widths.size(), " widths for ", dim, " inputs");
  if (o.max_nodes < 1) fail("forward selection: max_nodes must be >= 1");
  if (!(o.lambda >= 0)) fail("forward selection: lambda must be >= 0");

  const Eigen::MatrixXd centres_all = rows_of(x, select_candidates(x, o.candidates));
  const Eigen::Index m = centres_all.rows();
  const int cap = std::min<int>(o.max_nodes, static_cast<int>(m));
  CandidatePool pool(gaussian_columns(x, centres_all, o.widths), y, cap);
  OrthogonalSet set(n, cap, y);
  std::vector<Eigen::Index> selected;
  std::vector<double> lambdas;
  double lambda = o.lambda;

  ForwardSelectionResult result;
  result.candidates = static_cast<int>(m);
  double best = std::numeric_limits<double>::infinity();
  int best_k = 0, since_best = 0;
  result.stop_reason = "max_nodes";

  Progress progress("OLS forward selection (nodes of at most " + std::to_string(cap) + ")", static_cast<std::size_t>(cap));
  while (static_cast<int>(selected.size()) < cap) {
    progress.update(selected.size());
    pool.compact_if_sparse();
    const Eigen::Index pick = pool.pick(lambda, o.collinear_tolerance, result.skipped_collinear);
    if (pick < 0) {
      result.termination = Termination::converged;  // every candidate tried: the best step is final
      result.stop_reason = "candidates_exhausted";
      break;
    }
    pool.kill(pick);
    const Eigen::Index k = set.k;
    if (!set.add(pool.h.col(pick), pool.coef.col(pick).head(k), pool.norm2(pick), o.collinear_tolerance)) {
      ++result.skipped_collinear;
      continue;
    }
    pool.absorb(k, set.q.col(k), set.qy(k));
    selected.push_back(pool.candidate_of[static_cast<std::size_t>(pick)]);

    if (o.reestimate_lambda) lambda = set.reestimate_lambda(lambda, static_cast<double>(n));
    lambdas.push_back(lambda);
    const double crit = set.criterion(o.criterion, lambda);
    result.criterion_history.push_back(crit);
    if (crit < best * (1.0 - 1e-12)) {
      best = crit;
      best_k = static_cast<int>(set.k);
      since_best = 0;
    } else if (++since_best >= o.patience) {
      result.termination = Termination::converged;
      result.stop_reason = "criterion_minimum";
      break;
    }
  }
  if (best_k == 0) fail("forward selection: no node could be added (all candidates collinear or the target is zero)");

  // Weights of the kept network: H_k a = Q_k t, t_k = qy_k d_k/(d_k + lambda)  =>  r_tilde a = t.
  const double lam = lambdas[static_cast<std::size_t>(best_k - 1)];
  Eigen::VectorXd t(best_k);
  for (Eigen::Index i = 0; i < best_k; ++i) t(i) = set.qy(i) * set.d(i) / (set.d(i) + lam);
  result.weights = set.r_tilde.topLeftCorner(best_k, best_k).triangularView<Eigen::Upper>().solve(t);
  result.centres.resize(best_k, dim);
  for (Eigen::Index i = 0; i < best_k; ++i) result.centres.row(i) = centres_all.row(selected[static_cast<std::size_t>(i)]);
  result.lambda = lam;
  result.criterion = best;
  const RidgeState s = ridge_state(set.d, set.qy, best_k, 0.0, lam);
  // |unregularised residual|^2 after best_k nodes, recomputed exactly.
  const Eigen::VectorXd r = y - set.q.leftCols(best_k) * set.qy.head(best_k);
  result.rss = r.squaredNorm() + s.rss;
  result.effective_parameters = s.gamma;
  result.steps = static_cast<int>(selected.size());
  return result;
}

}  // namespace gyrosid
