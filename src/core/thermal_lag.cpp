#include "core/thermal_lag.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"

namespace gyrosid {

double PiecewiseLinear::at(double time) const {
  if (t.empty()) fail("PiecewiseLinear: no knots");
  if (time <= t.front()) return v.front();
  if (time >= t.back()) return v.back();
  const auto it = std::upper_bound(t.begin(), t.end(), time);
  const std::size_t i = static_cast<std::size_t>(it - t.begin()) - 1;
  const double h = t[i + 1] - t[i];
  return h > 0 ? v[i] + (v[i + 1] - v[i]) * (time - t[i]) / h : v[i + 1];
}

double PiecewiseLinear::slope_after(double time) const {
  if (t.size() < 2 || time < t.front() || time >= t.back()) return 0.0;
  const auto it = std::upper_bound(t.begin(), t.end(), time);
  const std::size_t i = static_cast<std::size_t>(it - t.begin()) - 1;
  const double h = t[i + 1] - t[i];
  return h > 0 ? (v[i + 1] - v[i]) / h : 0.0;
}

void PiecewiseLinear::append(double time, double value) {
  if (!t.empty() && time < t.back()) fail("PiecewiseLinear: knot at ", time, " s precedes ", t.back(), " s");
  t.push_back(time);
  v.push_back(value);
}

ThermalLagResponse thermal_lag_response(const ThermalLagOptions& options, const PiecewiseLinear& input,
                                        const std::vector<double>& query_times) {
  if (options.delay_s < 0) fail("thermal lag: delay_s = ", options.delay_s, " must be >= 0");
  for (double tau : options.tau_s)
    if (!(tau >= 0)) fail("thermal lag: tau_s = ", tau, " must be >= 0");
  if (input.t.empty()) fail("thermal lag: empty input signal");

  // Delayed input u(t) = input(t - delay): shift the knots.
  PiecewiseLinear u = input;
  for (double& time : u.t) time += options.delay_s;

  // Active (non-zero) stages; stage k's output is the output of the last active stage at or before k.
  std::vector<double> taus;
  std::vector<int> source(options.tau_s.size(), -1);  // -1 = the input itself
  for (std::size_t k = 0; k < options.tau_s.size(); ++k) {
    if (options.tau_s[k] > 0) taus.push_back(options.tau_s[k]);
    source[k] = static_cast<int>(taus.size()) - 1;
  }
  const int n = static_cast<int>(taus.size());

  // Augmented generator M for z = [x_1..x_n, u, s].
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n + 2, n + 2);
  for (int k = 0; k < n; ++k) {
    m(k, k) = -1.0 / taus[k];
    m(k, k == 0 ? n : k - 1) = 1.0 / taus[k];
  }
  m(n, n + 1) = 1.0;
  std::map<long long, Eigen::MatrixXd> cache;  // exp(M h) by h in nanoseconds
  auto propagator = [&](double h) -> const Eigen::MatrixXd& {
    const long long key = std::llround(h * 1e9);
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, (m * h).exp()).first;
    return it->second;
  };

  ThermalLagResponse response;
  response.stage.assign(options.tau_s.size(), std::vector<double>(query_times.size()));
  response.output_rate.resize(query_times.size());
  if (query_times.empty()) return response;

  double time = std::min(query_times.front(), u.t.front());
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, u.at(time));
  std::size_t knot = static_cast<std::size_t>(std::upper_bound(u.t.begin(), u.t.end(), time) - u.t.begin());

  for (std::size_t i = 0; i < query_times.size(); ++i) {
    const double target = query_times[i];
    if (i > 0 && target < query_times[i - 1]) fail("thermal lag: query times must be ascending");
    // Advance over each linear piece up to the target.
    while (time < target) {
      while (knot < u.t.size() && u.t[knot] <= time) ++knot;
      const double next = knot < u.t.size() ? std::min(u.t[knot], target) : target;
      const double h = next - time;
      if (n > 0 && h > 0) {
        Eigen::VectorXd z(n + 2);
        z.head(n) = x;
        z(n) = u.at(time);
        z(n + 1) = u.slope_after(time);
        x = (propagator(h) * z).head(n);
      }
      time = next;
    }
    const double u_now = u.at(target);
    for (std::size_t k = 0; k < options.tau_s.size(); ++k) {
      response.stage[k][i] = source[k] < 0 ? u_now : x(source[k]);
    }
    if (n == 0) {
      response.output_rate[i] = u.slope_after(target);
    } else {
      const double upstream = n == 1 ? u_now : x(n - 2);
      response.output_rate[i] = (upstream - x(n - 1)) / taus[n - 1];
    }
  }
  return response;
}

}  // namespace gyrosid
