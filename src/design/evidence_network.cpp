#include "design/evidence_network.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>

#include "core/bounded_search.h"
#include "core/error.h"
#include "core/format.h"
#include "model/gaussian_node.h"
#include "solvers/bayes/bayes_fit.h"
#include "solvers/common/candidates.h"

namespace gyrosid::design {

std::string NetworkSearchOptions::validate() const {
  if (nodes < 1) return "network search: at least one node";
  if (!(min_width > 0 && min_width <= scan_min && scan_min <= scan_max && scan_max <= max_width)) {
    return "network search: need 0 < min_width <= scan_min <= scan_max <= max_width";
  }
  if (scan < 1 || evaluations < 0) return "network search: scan >= 1 and evaluations >= 0";
  if (given_widths.size() != 0 && (given_widths.size() != 2 || !(given_widths.array() > 0).all())) return "network search: two positive given widths";
  if (!(given_prior_sd_radps >= 0)) return "network search: the given prior sd must be >= 0";
  return "";
}

Eigen::MatrixXd NetworkNodes::columns(const Signals& s) const {
  Eigen::MatrixXd x(s.size(), 2);
  x.col(0) = (s.rate.array() - offset(0)) / scale(0);
  x.col(1) = (s.temp_c.array() - offset(1)) / scale(1);
  return gaussian_columns(x, centres, widths);
}

PhysicsProjection::PhysicsProjection(const Eigen::MatrixXd& physics_whitened) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(physics_whitened);
  q_ = qr.householderQ() * Eigen::MatrixXd::Identity(physics_whitened.rows(), qr.rank());
}

ExpectedEvidence::ExpectedEvidence(const Eigen::MatrixXd& phi_p, const Eigen::VectorXd& y0_p, double residual_dof)
    : y2_(y0_p.squaredNorm()), dof_(residual_dof) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(phi_p.cols(), phi_p.cols());
  s.selfadjointView<Eigen::Lower>().rankUpdate(phi_p.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(s.selfadjointView<Eigen::Lower>()));
  lambda_ = eig.eigenvalues().cwiseMax(0.0);
  b2_ = (eig.eigenvectors().transpose() * (phi_p.transpose() * y0_p)).cwiseAbs2();
  const double floor = 1e-12 * std::max(1e-300, lambda_.maxCoeff());
  for (Eigen::Index i = 0; i < lambda_.size(); ++i) {
    if (lambda_(i) <= floor) lambda_(i) = 0.0, b2_(i) = 0.0;  // no information: no term (log alpha - log alpha)
  }
}

double ExpectedEvidence::gamma(double log_alpha) const {
  const double a = std::exp(log_alpha);
  return (lambda_.array() / (a + lambda_.array())).sum();
}

double ExpectedEvidence::at(double log_alpha) const {
  const double a = std::exp(log_alpha);
  double v = -y2_ - dof_;
  for (Eigen::Index i = 0; i < lambda_.size(); ++i) {
    if (lambda_(i) == 0.0) continue;
    v += log_alpha - std::log(a + lambda_(i)) + b2_(i) / (a + lambda_(i)) + lambda_(i) / (a + lambda_(i));
  }
  return v;
}

double ExpectedEvidence::best_log_alpha() const {
  const double top = std::log(std::max(1e-300, lambda_.maxCoeff()));
  // alpha far above every lambda switches the network off (the limit -|y0_p|^2 - N'); far below, every
  // informed direction pays log(alpha / lambda).
  double best_u = top + 12.0, best = at(best_u);
  for (double u = top - 46.0; u <= top + 12.0; u += 0.5) {
    if (const double v = at(u); v > best) best = v, best_u = u;
  }
  double lo = best_u - 0.5, hi = best_u + 0.5;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = at(x1), f2 = at(x2);
  for (int k = 0; k < 40; ++k) {
    if (f1 > f2) hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = at(x1);
    else lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = at(x2);
  }
  const double u = 0.5 * (lo + hi);
  return at(u) >= best ? u : best_u;
}

NetworkNodes expected_evidence_network(const Observations& o, const Eigen::MatrixXd& physics, const NoiseSpec& noise,
                                       const NetworkSearchOptions& opt) {
  if (auto p = opt.validate(); !p.empty()) fail("design: ", p);
  const Eigen::Index n = o.size();
  if (physics.rows() != n) fail("design: ", physics.rows(), " physics rows for ", n, " observations");
  NetworkNodes net;
  // The calibration's normalisation: each input's range along the recording onto [-1, 1].
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd& v = k == 0 ? o.inputs.rate : o.inputs.temp_c;
    const double lo = v.minCoeff(), hi = v.maxCoeff();
    net.offset(k) = 0.5 * (lo + hi);
    net.scale(k) = hi > lo ? 0.5 * (hi - lo) : 1.0;
  }
  Eigen::MatrixXd x(n, 2);
  x.col(0) = (o.inputs.rate.array() - net.offset(0)) / net.scale(0);
  x.col(1) = (o.inputs.temp_c.array() - net.offset(1)) / net.scale(1);
  net.centres = rows_of(x, select_candidates(x, opt.nodes));

  // Physics and target whitened once; the physics' span (rank-safe) projected off everything.
  Eigen::MatrixXd fy(n, physics.cols() + 1);
  fy << physics, o.true_error;
  const Eigen::MatrixXd w = whiten(fy, o.inputs.t_s, o.weight_s, noise);
  const PhysicsProjection physics_span(w.leftCols(physics.cols()));
  Eigen::MatrixXd y = w.rightCols(1);
  physics_span.project(y);
  const Eigen::VectorXd y0_p = y.col(0);

  struct Best {
    double value = -INFINITY, log_alpha = 0.0, gamma = 0.0;
    Eigen::RowVectorXd widths;
  } best;
  auto evaluate = [&](const Eigen::RowVectorXd& widths) {
    Eigen::MatrixXd phi = whiten(gaussian_columns(x, net.centres, widths), o.inputs.t_s, o.weight_s, noise);
    physics_span.project(phi);
    const ExpectedEvidence ev(phi, y0_p, physics_span.residual_dof());
    // alpha = 1 / sd^2 in whitened units: the columns are divided by the noise, not the weights
    const double u = opt.given_prior_sd_radps > 0 ? -2.0 * std::log(opt.given_prior_sd_radps) : ev.best_log_alpha(), v = ev.at(u);
    if (v > best.value) best = {v, u, ev.gamma(u), widths};
    return v;
  };
  if (opt.given_widths.size() == 2) {
    evaluate(opt.given_widths);
  } else {
    // Scan of one common width, then the per-input widths from the best, bounded below where an input was
    // recorded at discrete levels (as the calibration: identifiable_min_widths).
    for (int i = 0; i < opt.scan; ++i) {
      const double f = opt.scan == 1 ? 0.5 : static_cast<double>(i) / (opt.scan - 1);
      evaluate(Eigen::RowVectorXd::Constant(2, std::exp(std::log(opt.scan_min) + f * (std::log(opt.scan_max) - std::log(opt.scan_min)))));
    }
    const std::vector<double> floors = identifiable_min_widths(x, opt.min_width);
    std::vector<double> lower(2), upper(2), start(2);
    for (std::size_t k = 0; k < 2; ++k) {
      lower[k] = std::log(floors[k]);
      upper[k] = std::log(std::max(opt.max_width, floors[k]));
      start[k] = std::clamp(std::log(best.widths(static_cast<Eigen::Index>(k))), lower[k], upper[k]);
    }
    if (opt.evaluations > 0) {
      BoundedSearchOptions so;
      so.algorithm = "LN_BOBYQA", so.max_evaluations = opt.evaluations, so.xtol_rel = 1e-3, so.initial_step = 0.3;
      minimize_bounded([&](const std::vector<double>& rho) { return -evaluate(Eigen::RowVector2d(std::exp(rho[0]), std::exp(rho[1]))); },
                       start, lower, upper, so);
    }
  }
  net.widths = best.widths;
  net.prior_sd_radps = std::exp(-0.5 * best.log_alpha);
  net.effective_parameters = best.gamma;
  net.expected_log_evidence = best.value;
  return net;
}

}  // namespace gyrosid::design
