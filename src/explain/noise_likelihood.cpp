#include "explain/noise_likelihood.h"

#include <algorithm>
#include <cmath>

#include "core/bounded_search.h"
#include "core/parallel.h"
#include "explain/linear_fit.h"

namespace gyrosid::explain {

Eigen::MatrixXd whiten_columns(const Whitener& w, const Eigen::MatrixXd& x) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(w.rows().size()), x.cols());
  parallel_for(x.cols(), [&](std::ptrdiff_t begin, std::ptrdiff_t end) { out.middleCols(begin, end - begin) = w.apply(x.middleCols(begin, end - begin)); }, 8);
  return out;
}

NoiseLikelihood::NoiseLikelihood(std::vector<Eigen::Index> rows, const std::vector<double>& t_s, const NoiseModel& start, double xtol)
    : rows_(std::move(rows)), t_s_(t_s), start_(start), gm_tau_s_(start.gm_var > 0 ? start.gm_tau_s : 100.0 * start.dt_s), xtol_(xtol) {
  const double span = rows_.empty() ? 0.0 : t_s_[static_cast<std::size_t>(rows_.back())] - t_s_[static_cast<std::size_t>(rows_.front())];
  max_log_tau_ = std::log(std::max(100.0 * start_.dt_s, span / 3.0));
  gm_tau_s_ = std::clamp(gm_tau_s_, 2.0 * start_.dt_s, std::exp(max_log_tau_));
}

NoiseModel NoiseLikelihood::model(const Optimum& at) const {
  NoiseModel m;
  m.dt_s = start_.dt_s;
  m.white_var = 1.0;
  m.rw_q = std::exp(at.log_ratios[0]);
  m.gm_var = std::exp(at.log_ratios[1]);
  m.gm_tau_s = std::exp(at.log_ratios[2]);
  return m;
}

double NoiseLikelihood::negative(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const std::array<double, 3>& v) const {
  const Whitener w(model({0.0, v}), rows_, t_s_);
  const double n = static_cast<double>(rows_.size());
  return 0.5 * n * std::log(whitened_rss(whiten_columns(w, x), w.apply(y)) / n) + 0.5 * w.log_determinant();
}

NoiseLikelihood::Optimum NoiseLikelihood::start() const {
  Optimum from;
  from.log_ratios = {std::clamp(std::log(std::max(start_.rw_q / start_.white_var, 1e-9)), -24.0, 2.0),
                     std::clamp(std::log(std::max(start_.gm_var / start_.white_var, 1e-6)), -24.0, 2.0), std::log(gm_tau_s_)};
  return from;
}

NoiseLikelihood::Optimum NoiseLikelihood::maximise(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const { return maximise(x, y, start()); }

NoiseLikelihood::Optimum NoiseLikelihood::maximise(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Optimum& from) const {
  BoundedSearchOptions bobyqa;
  bobyqa.xtol_abs = xtol_;
  bobyqa.max_evaluations = 120;
  const double min_log_tau = std::log(2.0 * start_.dt_s);
  const BoundedSearchResult r = minimize_bounded([&](const std::vector<double>& v) { return negative(x, y, {v[0], v[1], v[2]}); },
                                                 {from.log_ratios[0], from.log_ratios[1], std::clamp(from.log_ratios[2], min_log_tau, max_log_tau_)},
                                                 {-25.0, -25.0, min_log_tau}, {3.0, 3.0, max_log_tau_}, bobyqa);
  return {-r.value, {r.x[0], r.x[1], r.x[2]}};
}

NoiseModel likelihood_noise_model(const Eigen::VectorXd& residual, const std::vector<Eigen::Index>& rows, const std::vector<double>& t_s,
                                  const NoiseModel& start) {
  if (rows.size() < 500 || !(start.white_var > 0)) return start;
  const NoiseLikelihood likelihood(rows, t_s, start);
  const Eigen::MatrixXd constant = Eigen::MatrixXd::Ones(residual.size(), 1);
  // A slow random walk and a Gauss-Markov process with a long time constant fit the same stretch of data
  // nearly equally well, so the likelihood has a basin for each; the Allan fit's start can sit in the worse
  // one. Also started from each slow part alone (sized so that it reaches the white variance over the
  // record), the best optimum kept.
  const double n = static_cast<double>(rows.size());
  NoiseLikelihood::Optimum best = likelihood.maximise(constant, residual);
  for (const std::array<double, 3>& from : {std::array<double, 3>{-std::log(n), -25.0, std::log(100.0 * start.dt_s)},
                                            std::array<double, 3>{-25.0, 0.0, std::log(n * start.dt_s / 10.0)}}) {
    const NoiseLikelihood::Optimum other = likelihood.maximise(constant, residual, {0.0, from});
    if (other.log_likelihood > best.log_likelihood) best = other;
  }
  NoiseModel m;
  m.dt_s = start.dt_s;
  m.white_var = 1.0;
  m.rw_q = std::exp(best.log_ratios[0]) > 1e-10 ? std::exp(best.log_ratios[0]) : 0.0;
  m.gm_var = std::exp(best.log_ratios[1]) > 1e-6 ? std::exp(best.log_ratios[1]) : 0.0;
  m.gm_tau_s = m.gm_var > 0 ? std::exp(best.log_ratios[2]) : 0.0;
  const Whitener w(m, rows, t_s);
  const double white = whitened_rss(w.apply(constant), w.apply(residual)) / static_cast<double>(rows.size());
  m.white_var = white, m.rw_q *= white, m.gm_var *= white;
  return m;
}

}  // namespace gyrosid::explain
