#include "solvers/bayes/evidence.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/parallel.h"

namespace gyrosid {
namespace {

// Rows per block of the Gram products: fixed, so sums are bit-identical whatever the thread count.
constexpr Eigen::Index kGramBlock = 2048;

// phi' phi and phi' y, summed over fixed row blocks computed in parallel.
void gram(const Eigen::MatrixXd& phi, const Eigen::VectorXd& y, Eigen::MatrixXd& s, Eigen::VectorXd& b) {
  const Eigen::Index n = phi.rows(), m = phi.cols();
  const Eigen::Index blocks = (n + kGramBlock - 1) / kGramBlock;
  std::vector<Eigen::MatrixXd> partial(static_cast<std::size_t>(blocks));
  parallel_for(blocks, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (std::ptrdiff_t k = begin; k < end; ++k) {
      const Eigen::Index r0 = k * kGramBlock, rows = std::min(kGramBlock, n - r0);
      Eigen::MatrixXd part = Eigen::MatrixXd::Zero(m, m);
      part.selfadjointView<Eigen::Lower>().rankUpdate(phi.middleRows(r0, rows).transpose());
      partial[static_cast<std::size_t>(k)] = std::move(part);
    }
  });
  s = Eigen::MatrixXd::Zero(m, m);
  for (const auto& part : partial) s += part;
  s = s.selfadjointView<Eigen::Lower>();
  b = phi.transpose() * y;
}

}  // namespace

FixedPart::FixedPart(const Eigen::MatrixXd& f, const Eigen::VectorXd& y, const Whitener* whitener) : whitener_(whitener) {
  const Eigen::MatrixXd fw = whitener ? whitener->apply(f) : f;
  const Eigen::VectorXd yw = whitener ? Eigen::VectorXd(whitener->apply(y)) : y;
  const Eigen::Index p = f.cols();
  log_det_terms_ = whitener ? -whitener->log_determinant() : 0.0;
  if (p == 0) {
    q_.resize(yw.size(), 0);
    r_.resize(0, 0);
    qy_.resize(0);
    y_p_ = yw;
    return;
  }
  if (fw.rows() <= p) fail("bayes: ", fw.rows(), " samples for ", p, " fixed columns");
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(fw);
  q_ = qr.householderQ() * Eigen::MatrixXd::Identity(fw.rows(), p);
  r_ = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  const double largest = r_.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < p; ++k) {
    const double rk = std::abs(r_(k, k));
    if (!(rk > 1e-10 * largest)) fail("bayes: fixed column ", k, " is (nearly) a combination of the others - the data do not identify it");
    log_det_terms_ -= 2.0 * std::log(rk);
  }
  qy_ = q_.transpose() * yw;
  y_p_ = yw - q_ * qy_;
}

void FixedPart::project(Eigen::MatrixXd& x) const {
  if (whitener_) x = whitener_->apply(x);
  if (q_.cols() > 0) x -= q_ * (q_.transpose() * x);
}

RbfEvidence::RbfEvidence(const Eigen::MatrixXd& phi_p, const FixedPart& fixed)
    : n_(fixed.samples() - fixed.columns()), fixed_terms_(fixed.log_determinant_terms()) {
  const Eigen::VectorXd& y = fixed.y_projected();
  if (n_ <= 0) fail("bayes: no samples left after the fixed columns");
  if (phi_p.cols() == 0) {  // no RBF part: the fixed columns alone (generalised least squares)
    r0_ = y.squaredNorm();
    return;
  }
  Eigen::MatrixXd s;
  Eigen::VectorXd b;
  gram(phi_p, y, s, b);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  if (eig.info() != Eigen::Success) fail("bayes: eigen-decomposition of the Gram matrix failed");
  lambda_ = eig.eigenvalues().cwiseMax(0.0);
  v_ = eig.eigenvectors();
  bt_ = v_.transpose() * b;
  // Directions with eigenvalues at round-off of the largest carry no data: no projection of y either.
  const double floor = 1e-14 * std::max(1.0, lambda_.maxCoeff()) * static_cast<double>(std::max<Eigen::Index>(1, lambda_.size()));
  c_ = Eigen::VectorXd::Zero(lambda_.size());
  double explained = 0.0;
  for (Eigen::Index i = 0; i < lambda_.size(); ++i) {
    if (lambda_(i) > floor) {
      c_(i) = bt_(i) * bt_(i) / lambda_(i);
      explained += c_(i);
    } else {
      lambda_(i) = 0.0, bt_(i) = 0.0;
    }
  }
  r0_ = std::max(0.0, y.squaredNorm() - explained);
}

RbfEvidence::Terms RbfEvidence::terms(double alpha, double beta) const {
  Terms t{r0_, 0.0, 0.0, 0.0};
  for (Eigen::Index i = 0; i < lambda_.size(); ++i) {
    const double den = alpha + beta * lambda_(i), mi = beta * bt_(i) / den, shrink = alpha / den;
    t.e_w += mi * mi;
    t.e_d += c_(i) * shrink * shrink;
    t.log_det += std::log(den);
    t.gamma += beta * lambda_(i) / den;
  }
  return t;
}

double RbfEvidence::log_evidence(const Precisions& p) const {
  const double alpha = std::exp(p.log_alpha), beta = std::exp(p.log_beta);
  const Terms t = terms(alpha, beta);
  const double m = static_cast<double>(lambda_.size()), n = static_cast<double>(n_);
  return 0.5 * (m * p.log_alpha + n * p.log_beta - beta * t.e_d - alpha * t.e_w - t.log_det - n * kLog2Pi + fixed_terms_);
}

double RbfEvidence::optimise(Precisions p, const EvidenceBounds& bounds) {
  const double n = static_cast<double>(n_);
  for (int it = 0; it < 2000; ++it) {
    const Terms t = terms(std::exp(p.log_alpha), std::exp(p.log_beta));
    Precisions next;
    next.log_alpha = t.e_w > 0 && t.gamma > 0 ? std::log(t.gamma / t.e_w) : bounds.max_log_alpha;
    next.log_beta = t.e_d > 0 && n > t.gamma ? std::log((n - t.gamma) / t.e_d) : bounds.max_log_beta;
    next.log_alpha = std::clamp(next.log_alpha, bounds.min_log_alpha, bounds.max_log_alpha);
    next.log_beta = std::clamp(next.log_beta, bounds.min_log_beta, bounds.max_log_beta);
    const double step = std::abs(next.log_alpha - p.log_alpha) + std::abs(next.log_beta - p.log_beta);
    p = next;
    if (step < 1e-10) break;
  }
  at_ = p;
  value_ = log_evidence(p);
  return value_;
}

double RbfEvidence::gamma() const { return terms(std::exp(at_.log_alpha), std::exp(at_.log_beta)).gamma; }

Eigen::VectorXd RbfEvidence::mean() const {
  const double alpha = std::exp(at_.log_alpha), beta = std::exp(at_.log_beta);
  const Eigen::ArrayXd den = alpha + beta * lambda_.array();
  return v_ * (beta * bt_.array() / den).matrix();
}

Eigen::MatrixXd RbfEvidence::covariance() const {
  const double alpha = std::exp(at_.log_alpha), beta = std::exp(at_.log_beta);
  const Eigen::VectorXd inv = (alpha + beta * lambda_.array()).inverse().matrix();
  return v_ * inv.asDiagonal() * v_.transpose();
}

Eigen::MatrixXd RbfEvidence::gradient_wrt_columns(const Eigen::MatrixXd& phi_p, const Eigen::VectorXd& y_p) const {
  const double beta = std::exp(at_.log_beta);
  const Eigen::VectorXd m = mean();
  const Eigen::VectorXd e = y_p - phi_p * m;
  Eigen::MatrixXd g = phi_p * covariance();
  g = beta * (e * m.transpose() - g);
  return g;
}

Eigen::VectorXd log_width_gradient(const Eigen::MatrixXd& g, const Eigen::MatrixXd& phi, const Eigen::MatrixXd& x,
                                   const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths) {
  const Eigen::Index m = centres.rows(), d = x.cols();
  // dphi_ij / d log r_k = phi_ij 2 u_ijk^2 (model/gaussian_node.h); per-node partial sums, added in order.
  Eigen::MatrixXd per_node(d, m);
  parallel_for(m, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      for (Eigen::Index k = 0; k < d; ++k) {
        const Eigen::ArrayXd u = (x.col(k).array() - centres(j, k)) / widths(k);
        per_node(k, j) = (g.col(j).array() * phi.col(j).array() * 2.0 * u.square()).sum();
      }
    }
  }, 8);
  return per_node.rowwise().sum();
}

}  // namespace gyrosid
