#include "design/information.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace gyrosid::design {

NoiseSpec NoiseSpec::of(const NoiseOptions& o) {
  NoiseSpec n;
  n.white_psd = o.arw_rad_rt_s * o.arw_rad_rt_s;
  n.markov = o.gauss_markov;
  for (const auto& gm : bias_instability_components(o.bias_instability_radps, o.bias_instability_tau_min_s,
                                                    o.bias_instability_tau_max_s, o.bias_instability_per_decade)) {
    n.markov.push_back(gm);
  }
  n.rrw_psd = o.rrw_rad_s_rt_s * o.rrw_rad_s_rt_s;
  return n;
}

Eigen::MatrixXd whiten(const Eigen::MatrixXd& a, const std::vector<double>& t, const Eigen::VectorXd& w, const NoiseSpec& noise,
                       double* log_determinant) {
  const Eigen::Index n = a.rows(), p = a.cols();
  if (static_cast<Eigen::Index>(t.size()) != n || w.size() != n) fail("whiten: ", n, " rows, ", t.size(), " times, ", w.size(), " weights");
  if (!noise.any()) fail("the sensor has no noise: a design minimises the noise-driven calibration error (give the sensor config its noise)");
  if (n == 0) return a;
  // Gauss-Markov processes faster than the typical spacing act as white noise of equal Allan variance.
  std::vector<double> sorted(w.data(), w.data() + n);
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const double spacing = sorted[static_cast<std::size_t>(n / 2)];
  double white_psd = noise.white_psd;
  std::vector<GaussMarkov> states;
  for (const auto& gm : noise.markov) {
    if (gm.tau_s <= spacing) white_psd += 2.0 * gm.sigma_radps * gm.sigma_radps * gm.tau_s;
    else states.push_back(gm);
  }
  const bool rrw = noise.rrw_psd > 0;
  const Eigen::Index m = static_cast<Eigen::Index>(states.size()) + (rrw ? 1 : 0);
  if (m == 0) {
    if (log_determinant) *log_determinant = (white_psd / w.array()).log().sum();
    return (a.array().colwise() * (w.array() / white_psd).sqrt()).matrix();
  }
  if (!(white_psd > 0)) fail("design: coloured noise without a white part cannot be whitened observation by observation");

  // Kalman filter on states [g_1..g_m', b]: y_k = sum g + b + v_k, var v_k = white_psd / w_k; the gains do not
  // depend on the data, so every column runs through the same recursion.
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(m, m), x = Eigen::MatrixXd::Zero(m, p), out(n, p);
  for (std::size_t i = 0; i < states.size(); ++i) cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) = std::pow(states[i].sigma_radps, 2);
  Eigen::VectorXd phi(m), q(m);
  double log_det = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double dt = k == 0 ? 0.0 : t[static_cast<std::size_t>(k)] - t[static_cast<std::size_t>(k - 1)];
    if (dt < 0) fail("whiten: observation times must be ascending");
    for (std::size_t i = 0; i < states.size(); ++i) {
      phi(static_cast<Eigen::Index>(i)) = std::exp(-dt / states[i].tau_s);
      q(static_cast<Eigen::Index>(i)) = std::pow(states[i].sigma_radps, 2) * (1.0 - std::pow(phi(static_cast<Eigen::Index>(i)), 2));
    }
    if (rrw) phi(m - 1) = 1.0, q(m - 1) = noise.rrw_psd * dt;
    x = phi.asDiagonal() * x;
    cov = phi.asDiagonal() * cov * phi.asDiagonal();
    cov.diagonal() += q;
    const Eigen::VectorXd ph = cov.rowwise().sum();  // P h, h = ones
    const double s = ph.sum() + white_psd / w(k);
    log_det += std::log(s);
    const Eigen::RowVectorXd innovation = a.row(k) - x.colwise().sum();
    out.row(k) = innovation / std::sqrt(s);
    x += (ph / s) * innovation;
    cov -= ph * ph.transpose() / s;
  }
  if (log_determinant) *log_determinant = log_det;
  return out;
}

Prior Prior::independent(const Eigen::VectorXd& sd) {
  if (!(sd.array() > 0).all()) fail("design: prior standard deviations must be positive");
  return {Eigen::VectorXd::Zero(sd.size()), sd.asDiagonal()};
}

LinearEstimate linear_estimate(const Eigen::MatrixXd& whitened, const Prior& prior, bool has_target) {
  const Eigen::Index p = prior.size();
  if (whitened.cols() != p + (has_target ? 1 : 0)) fail("linear_estimate: ", whitened.cols(), " columns for ", p, " parameters");
  const Eigen::MatrixXd scaled = whitened.leftCols(p) * prior.root;
  Eigen::MatrixXd info = Eigen::MatrixXd::Zero(p, p);
  info.selfadjointView<Eigen::Lower>().rankUpdate(scaled.transpose());
  info = info.selfadjointView<Eigen::Lower>();
  Eigen::MatrixXd precision = info;
  precision.diagonal().array() += 1.0;
  const Eigen::LLT<Eigen::MatrixXd> llt(precision);  // eigenvalues >= 1: always positive definite
  if (llt.info() != Eigen::Success) fail("linear_estimate: the precision is not positive definite (non-finite columns?)");
  LinearEstimate e;
  e.prior = prior;
  e.posterior = llt.solve(Eigen::MatrixXd::Identity(p, p));
  e.estimator = e.posterior * info * e.posterior;
  if (has_target) e.expected = llt.solve(scaled.transpose() * (whitened.col(p) - whitened.leftCols(p) * prior.mean));
  e.log_det_information = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  return e;
}

}  // namespace gyrosid::design
