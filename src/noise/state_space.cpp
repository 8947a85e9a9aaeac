#include "noise/state_space.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "noise/allan.h"
#include "noise/identify.h"
#include "noise/processes.h"

namespace gyrosid {

double NoiseModel::allan_variance(double tau) const {
  double v = white_var * dt_s / tau + rw_q / dt_s * tau / 3.0;
  if (gm_var > 0) v += gauss_markov_allan_variance(std::sqrt(gm_var), gm_tau_s, tau);
  return v;
}

double NoiseModel::stationary_sigma() const { return std::sqrt(white_var + gm_var); }

nlohmann::json NoiseModel::to_json() const {
  nlohmann::json j = {{"white_sigma", std::sqrt(white_var)}, {"dt_s", dt_s}};
  if (rw_q > 0) j["rate_random_walk_per_rt_h"] = std::sqrt(rw_q / dt_s) * 60.0;
  if (gm_var > 0) j["gauss_markov"] = {{"sigma", std::sqrt(gm_var)}, {"tau_s", gm_tau_s}};
  return j;
}

NoiseModel NoiseModel::from_json(const nlohmann::json& j) {
  NoiseModel m;
  m.dt_s = j.at("dt_s").get<double>();
  m.white_var = std::pow(j.at("white_sigma").get<double>(), 2);
  if (j.contains("rate_random_walk_per_rt_h")) m.rw_q = std::pow(j["rate_random_walk_per_rt_h"].get<double>() / 60.0, 2) * m.dt_s;
  if (j.contains("gauss_markov")) {
    m.gm_var = std::pow(j["gauss_markov"].at("sigma").get<double>(), 2);
    m.gm_tau_s = j["gauss_markov"].at("tau_s").get<double>();
  }
  return m;
}

std::vector<std::vector<Eigen::Index>> contiguous_runs(const std::vector<Eigen::Index>& rows, const std::vector<int>& segment) {
  std::vector<std::vector<Eigen::Index>> runs;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Eigen::Index i = rows[k];
    const bool joins = k > 0 && i == rows[k - 1] + 1 &&
                       segment[static_cast<std::size_t>(i)] == segment[static_cast<std::size_t>(rows[k - 1])];
    if (!joins) runs.emplace_back();
    runs.back().push_back(i);
  }
  return runs;
}

NoiseModel whitening_model(const CompositeNoise& composite, double dt, double tau_low, double tau_high) {
  CompositeNoise slow = composite;
  slow.quantization = slow.filter = 0.0;
  std::vector<AllanPoint> curve;
  const int points = 40;
  for (int i = 0; i < points; ++i) {
    AllanPoint p;
    p.tau_s = tau_low * std::pow(tau_high / tau_low, static_cast<double>(i) / (points - 1));
    p.adev = std::sqrt(std::max(0.0, slow.allan_variance(p.tau_s)));
    p.edf = 1.0;
    curve.push_back(p);
  }
  const GaussMarkovFit fit = fit_gauss_markov(curve, true, true);
  NoiseModel m;
  m.dt_s = dt;
  m.white_var = fit.angle_random_walk * fit.angle_random_walk / dt;
  m.rw_q = fit.rate_random_walk * fit.rate_random_walk * dt;
  m.gm_var = fit.sigma * fit.sigma;
  m.gm_tau_s = fit.tau_s;
  if (m.gm_var > 0 && m.gm_tau_s < 2.0 * dt) {
    // Correlated over less than two samples: white noise at this sampling. Its Allan variance tends to
    // 2 sigma^2 tau_c / tau, that of white noise of per-sample variance v to v dt / tau - folded in with that v.
    m.white_var += 2.0 * m.gm_var * m.gm_tau_s / dt;
    m.gm_var = 0.0, m.gm_tau_s = 0.0;
  }
  if (!(m.white_var > 0)) m.white_var = 1e-12 * (m.gm_var + 1.0);
  return m;
}

NoiseModel fit_noise_model(const Eigen::VectorXd& x, const std::vector<std::vector<Eigen::Index>>& runs, double dt, NoiseStart start,
                           NoiseIdentification* identified) {
  NoiseModel m;
  m.dt_s = dt;
  const auto longest = std::max_element(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
  if (longest == runs.end()) fail("noise model: no samples");
  if (longest->size() < 500) {
    double ss = 0.0, n = 0.0;
    for (const auto& run : runs) {
      for (Eigen::Index i : run) ss += x(i) * x(i), n += 1.0;
    }
    m.white_var = ss / std::max(1.0, n);
    return m;
  }
  std::vector<double> v;
  v.reserve(longest->size());
  for (Eigen::Index i : *longest) v.push_back(x(i));
  if (start == NoiseStart::identified) {
    NoiseIdOptions options;
    options.max_gauss_markov = 2;
    NoiseIdentification id = identify_noise(v, dt, options);
    const NoiseModel m_id = whitening_model(id.model, dt, id.fit_tau_low_s, id.fit_tau_high_s);
    if (identified) *identified = std::move(id);
    return m_id;
  }
  const GaussMarkovFit fit = fit_gauss_markov(overlapping_allan_deviation(v, dt), true, true);
  m.white_var = fit.angle_random_walk * fit.angle_random_walk / dt;
  m.rw_q = fit.rate_random_walk * fit.rate_random_walk * dt;
  m.gm_var = fit.sigma * fit.sigma;
  m.gm_tau_s = fit.tau_s;
  if (m.gm_var > 0 && m.gm_tau_s < dt) {
    // Correlated over less than a sample: white noise at this sampling, folded in with the per-sample variance
    // whose Allan variance it has at long tau (2 sigma^2 tau_c / tau against v dt / tau).
    const double tau = 1e3 * dt;
    m.white_var += gauss_markov_allan_variance(fit.sigma, m.gm_tau_s, tau) * tau / dt;
    m.gm_var = 0.0, m.gm_tau_s = 0.0;
  }
  if (!(m.white_var > 0)) m.white_var = 1e-12 * (m.gm_var + 1.0);
  return m;
}

Whitener::Whitener(NoiseModel model, std::vector<Eigen::Index> rows, const std::vector<double>& t_s, RandomWalkStart start)
    : model_(model), rows_(std::move(rows)) {
  if (rows_.empty()) fail("noise model: nothing to whiten");
  // The Kalman filter's gains and innovation variances depend on the model and the sample times only.
  const double diffuse = 1e6 * (model_.white_var + model_.gm_var);
  const double rw0 = model_.rw_q > 0 && start == RandomWalkStart::diffuse ? diffuse : 0.0;
  Eigen::Matrix2d p = Eigen::Vector2d(rw0, model_.gm_var).asDiagonal();
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    double phi = 0.0;
    if (k > 0) {
      const double steps = (t_s[static_cast<std::size_t>(rows_[k])] - t_s[static_cast<std::size_t>(rows_[k - 1])]) / model_.dt_s;
      phi = model_.gm_var > 0 ? std::exp(-steps * model_.dt_s / model_.gm_tau_s) : 0.0;
      const Eigen::Matrix2d f = Eigen::Vector2d(1.0, phi).asDiagonal();
      p = f * p * f.transpose();
      p(0, 0) += model_.rw_q * steps;
      p(1, 1) += model_.gm_var * (1.0 - phi * phi);
    }
    const double s = p.sum() + model_.white_var;  // H = [1 1]
    const Eigen::Vector2d gain = p.rowwise().sum() / s;
    p -= gain * p.colwise().sum();
    decay_.push_back(phi);
    inv_sd_.push_back(1.0 / std::sqrt(s));
    gain_.push_back(gain);
    log_det_ += std::log(s);
  }
}

Eigen::MatrixXd Whitener::apply(const Eigen::MatrixXd& x) const {
  // Column by column: each column's filter is a scalar recursion over contiguous memory (the same arithmetic,
  // in the same order per element, as filtering all columns of a row at once, without a temporary per row).
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows_.size()), x.cols());
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    const double* in = x.col(c).data();
    double* o = out.col(c).data();
    double level = 0.0, wander = 0.0;  // the filtered random-walk and Gauss-Markov states
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      wander *= decay_[r];
      const double innovation = in[rows_[r]] - level - wander;
      o[r] = innovation * inv_sd_[r];
      level += gain_[r](0) * innovation;
      wander += gain_[r](1) * innovation;
    }
  }
  return out;
}

Eigen::MatrixXd Whitener::apply_transpose(const Eigen::MatrixXd& z, Eigen::Index recording_rows) const {
  // apply() is, per sample r: s- = D_r s+, nu = x_r - [1 1] s-, out_r = nu / sd_r, s+ = s- + k_r nu.
  // Its transpose runs backwards with the adjoints (hats) of the same steps.
  if (z.rows() != static_cast<Eigen::Index>(rows_.size())) fail("noise model: adjoint of ", z.rows(), " rows for ", rows_.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(recording_rows, z.cols());
  Eigen::MatrixXd state = Eigen::MatrixXd::Zero(2, z.cols());  // adjoint of s+ after sample r
  for (std::size_t k = rows_.size(); k-- > 0;) {
    const auto r = static_cast<Eigen::Index>(k);
    const Eigen::RowVectorXd nu = z.row(r) * inv_sd_[k] + gain_[k](0) * state.row(0) + gain_[k](1) * state.row(1);
    out.row(rows_[k]) = nu;
    state.row(0) -= nu;  // adjoint of s-: s+hat - [1 1]' nu_hat
    state.row(1) -= nu;
    state.row(1) *= decay_[k];  // adjoint of s+ of the previous sample: D_r' s-hat
  }
  return out;
}

}  // namespace gyrosid
