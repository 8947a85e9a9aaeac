#include "design/sensor_posterior.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/units.h"
#include "design/information.h"
#include "sim/simulate.h"

namespace gyrosid::design {

double recording_log_likelihood(const GyroSensor& member, const TableProfile& programme, const std::vector<double>& t_s,
                                const std::vector<double>& gyro_dps) {
  const auto n = static_cast<Eigen::Index>(t_s.size());
  if (n < 2 || gyro_dps.size() != t_s.size()) fail("likelihood of '", member.name, "': ", t_s.size(), " times and ", gyro_dps.size(), " outputs");
  NoiseSpec noise = NoiseSpec::of(member.noise);
  const double dt = (t_s.back() - t_s.front()) / static_cast<double>(n - 1);
  // Angle quantization Q: the rate error (e_{k-1} - e_k) Q / dt with e uniform on [0, 1), taken as white.
  noise.white_psd += member.quantization_rad * member.quantization_rad / (6.0 * dt);
  if (!noise.any()) fail("prior member '", member.name, "' has no noise: the likelihood of a recording under it is undefined");
  const GyroSensor exact = std::get<GyroSensor>(without_noise(member));
  const Excitation excitation = excite(programme, t_s, member.thermal.lag_options());
  const GyroOutput predicted = simulate_single(exact, excitation, 0);
  Eigen::MatrixXd a(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    a(k, 0) = units::dps_to_radps(gyro_dps[static_cast<std::size_t>(k)]) - predicted.rate_radps[static_cast<std::size_t>(k)];
    a(k, 1) = 1.0;
  }
  double log_det = 0.0;
  const Eigen::MatrixXd w = whiten(a, t_s, Eigen::VectorXd::Constant(n, dt), noise, &log_det);
  const double uu = w.col(1).squaredNorm(), ur = w.col(1).dot(w.col(0));
  return -0.5 * (log_det + w.col(0).squaredNorm() - ur * ur / uu + std::log(uu));
}

double effective_members(const std::vector<double>& weights) {
  double sum = 0.0, squares = 0.0;
  for (double w : weights) sum += w, squares += w * w;
  return squares > 0 ? sum * sum / squares : 0.0;
}

namespace {

std::vector<double> tempered(const std::vector<double>& prior, const std::vector<double>& log_l, double eta) {
  const double top = *std::max_element(log_l.begin(), log_l.end());
  std::vector<double> w(prior.size());
  for (std::size_t m = 0; m < w.size(); ++m) w[m] = prior[m] * std::exp(eta * (log_l[m] - top));
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (double& x : w) x /= sum;
  return w;
}

}  // namespace

SensorPosterior tempered_posterior(const std::vector<double>& prior_weights, const std::vector<double>& log_likelihood,
                                   double min_effective_members) {
  if (prior_weights.empty() || prior_weights.size() != log_likelihood.size()) {
    fail("posterior: ", prior_weights.size(), " prior weights for ", log_likelihood.size(), " log-likelihoods");
  }
  for (std::size_t m = 0; m < prior_weights.size(); ++m) {
    if (!(prior_weights[m] > 0)) fail("posterior: the prior weight of member ", m + 1, " is not positive");
    if (!std::isfinite(log_likelihood[m])) fail("posterior: the log-likelihood of member ", m + 1, " is not finite");
  }
  SensorPosterior p;
  p.log_likelihood = log_likelihood;
  const double floor = std::min(min_effective_members, 0.5 * effective_members(prior_weights));
  double eta = 1.0;
  if (effective_members(tempered(prior_weights, log_likelihood, 1.0)) < floor) {
    double lo = 0.0, hi = 1.0;  // ESS(lo) >= floor > ESS(hi)
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (effective_members(tempered(prior_weights, log_likelihood, mid)) >= floor ? lo : hi) = mid;
    }
    eta = lo;
  }
  p.learning_rate = eta;
  p.weights = tempered(prior_weights, log_likelihood, eta);
  p.effective_members = effective_members(p.weights);
  return p;
}

}  // namespace gyrosid::design
