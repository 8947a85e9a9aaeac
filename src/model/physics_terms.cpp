#include "model/physics_terms.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/thermal_lag.h"
#include "core/units.h"
#include "model/dataset.h"
#include "sensor/spline_surface.h"

namespace gyrosid {

const Eigen::VectorXd& Signals::channel(const std::string& name) const {
  const auto it = channels.find(name);
  if (it == channels.end()) {
    std::string known;
    for (const auto& [k, v] : channels) known += (known.empty() ? "" : ", ") + k;
    fail("physics term needs the channel '", name, "', which the data lack (channels: ", known.empty() ? "none" : known, ")");
  }
  return it->second;
}

nlohmann::json TermScaling::to_json() const {
  return {{"t_ref_c", t_ref_c}, {"t_scale_c", t_scale_c}, {"rate_scale_radps", rate_scale_radps},
          {"hysteresis_threshold_c_per_s", hysteresis_threshold_c_per_s}};
}

TermScaling TermScaling::from_json(const nlohmann::json& j) {
  TermScaling s;
  s.t_ref_c = j.at("t_ref_c").get<double>();
  s.t_scale_c = j.at("t_scale_c").get<double>();
  s.rate_scale_radps = j.at("rate_scale_radps").get<double>();
  s.hysteresis_threshold_c_per_s = j.at("hysteresis_threshold_c_per_s").get<double>();
  if (!(s.t_scale_c > 0) || !(s.rate_scale_radps > 0) || !(s.hysteresis_threshold_c_per_s > 0)) {
    fail("physics terms: scales must be positive");
  }
  return s;
}

TermScaling TermScaling::of(const Signals& s) {
  TermScaling out;
  if (s.size() == 0) return out;
  const double lo = s.temp_c.minCoeff(), hi = s.temp_c.maxCoeff();
  out.t_ref_c = 0.5 * (lo + hi);
  out.t_scale_c = std::max(1.0, 0.5 * (hi - lo));  // a probe's quantisation is no temperature range
  const double peak = s.rate.cwiseAbs().maxCoeff();
  out.rate_scale_radps = peak > units::dps_to_radps(1.0) ? peak : 1.0;
  return out;
}

int Term::size() const {
  switch (kind) {
    case TermKind::bias_temperature: return static_cast<int>(orders.size());
    case TermKind::scale_factor: return static_cast<int>(sf_orders.size());
    case TermKind::scale_factor_surface: return static_cast<int>(grid_temps_c.size() * grid_rates_dps.size());
    case TermKind::channel:
    case TermKind::channel_squared: return static_cast<int>(channels.size());
    default: return 1;
  }
}

std::vector<std::string> Term::column_names() const {
  std::vector<std::string> out;
  switch (kind) {
    case TermKind::bias_temperature:
      for (int k : orders) out.push_back(str_cat("dT^", k));
      break;
    case TermKind::scale_factor:
      for (const auto& p : sf_orders) out.push_back(str_cat("w dT^", p[0], " u^", p[1]));
      break;
    case TermKind::scale_factor_surface:
      for (double t : grid_temps_c)
        for (double w : grid_rates_dps) out.push_back(str_cat("w B(", t, " C, ", w, " dps)"));
      break;
    case TermKind::channel:
      out = channels;
      break;
    case TermKind::channel_squared:
      for (const auto& c : channels) out.push_back(c + "^2");
      break;
    default:
      out.emplace_back(to_string(kind));
  }
  return out;
}

nlohmann::json Term::to_json() const {
  nlohmann::json j = {{"kind", to_string(kind)}};
  if (!orders.empty()) j["orders"] = orders;
  if (!sf_orders.empty()) j["sf_orders"] = sf_orders;
  if (!channels.empty()) j["channels"] = channels;
  if (kind == TermKind::scale_factor_surface) j["grid"] = {{"temperatures_c", grid_temps_c}, {"rates_dps", grid_rates_dps}};
  if (kind == TermKind::warmup) j["tau_s"] = tau_s;
  return j;
}

Term Term::from_json(const nlohmann::json& j) {
  Term t;
  t.kind = parse_enum<TermKind>(j.at("kind").get<std::string>(), "physics term");
  if (j.contains("orders")) t.orders = j["orders"].get<std::vector<int>>();
  if (j.contains("sf_orders")) t.sf_orders = j["sf_orders"].get<std::vector<std::array<int, 2>>>();
  if (j.contains("channels")) t.channels = j["channels"].get<std::vector<std::string>>();
  t.tau_s = j.value("tau_s", 0.0);
  if (t.kind == TermKind::scale_factor_surface) {
    t.grid_temps_c = j.at("grid").at("temperatures_c").get<std::vector<double>>();
    t.grid_rates_dps = j.at("grid").at("rates_dps").get<std::vector<double>>();
    for (const auto* g : {&t.grid_temps_c, &t.grid_rates_dps}) {
      if (g->size() < 2 || !std::is_sorted(g->begin(), g->end()) || std::adjacent_find(g->begin(), g->end()) != g->end()) {
        fail("physics term scale_factor_surface: grids need at least two strictly increasing values");
      }
    }
  }
  if (t.kind == TermKind::warmup && !(t.tau_s > 0)) fail("physics term warmup: tau_s must be positive");
  for (int k : t.orders) {
    if (k < 1 || k > 8) fail("physics term bias_temperature: order ", k, " outside [1, 8]");
  }
  for (const auto& p : t.sf_orders) {
    if (p[0] < 0 || p[0] > 6 || p[1] < 0 || p[1] > 8) fail("physics term scale_factor: orders (", p[0], ", ", p[1], ") out of range");
  }
  if (t.size() == 0) fail("physics term ", to_string(t.kind), " has no columns");
  return t;
}

CoilTemperature coil_temperature(const Signals& s, double tau) {
  CoilTemperature c;
  std::vector<double> probe(s.temp_c.data(), s.temp_c.data() + s.size());
  if (tau > 0) {
    const ThermalLagResponse r = thermal_lag_response({0.0, {tau}}, PiecewiseLinear{s.t_s, probe}, s.t_s);
    c.temp_c = Eigen::Map<const Eigen::VectorXd>(r.stage[0].data(), s.size());
    c.rate_c_per_s = Eigen::Map<const Eigen::VectorXd>(r.output_rate.data(), s.size());
  } else {
    c.temp_c = s.temp_c;
    const std::vector<double> rate = time_derivative(s.t_s, probe);
    c.rate_c_per_s = Eigen::Map<const Eigen::VectorXd>(rate.data(), s.size());
  }
  return c;
}

Eigen::VectorXd thermal_branch(const Signals& s, const CoilTemperature& coil, const TermScaling& scaling) {
  const Eigen::Index n = s.size();
  Eigen::VectorXd branch = Eigen::VectorXd::Zero(n);
  if (n == 0) return branch;
  // The temperature change over a +-30 s window (a probe's quantisation and noise make the sample-to-sample
  // rate useless), compared with the threshold rate times the window.
  std::size_t lo = 0, hi = 0;
  double state = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = s.t_s[static_cast<std::size_t>(i)];
    while (s.t_s[lo] < t - 30.0) ++lo;
    while (hi + 1 < static_cast<std::size_t>(n) && s.t_s[hi + 1] <= t + 30.0) ++hi;
    const double span = s.t_s[hi] - s.t_s[lo];
    if (span > 0) {
      const double rate = (coil.temp_c(static_cast<Eigen::Index>(hi)) - coil.temp_c(static_cast<Eigen::Index>(lo))) / span;
      if (rate > scaling.hysteresis_threshold_c_per_s) state = 0.5;
      else if (rate < -scaling.hysteresis_threshold_c_per_s) state = -0.5;
    }
    branch(i) = state;
  }
  // Before the first ramp the branch is unknown: take the first one seen.
  Eigen::Index first = 0;
  while (first < n && branch(first) == 0.0) ++first;
  if (first < n) branch.head(first).setConstant(branch(first));
  return branch;
}

Eigen::MatrixXd term_columns(const Term& term, const Signals& s, const CoilTemperature& coil, const TermScaling& sc) {
  const Eigen::Index n = s.size();
  Eigen::MatrixXd x(n, term.size());
  const Eigen::ArrayXd dt = (coil.temp_c.array() - sc.t_ref_c) / sc.t_scale_c;
  const double t0 = s.t_s.empty() ? 0.0 : s.t_s.front();
  switch (term.kind) {
    case TermKind::bias:
      x.setOnes();
      break;
    case TermKind::bias_temperature:
      for (std::size_t c = 0; c < term.orders.size(); ++c) x.col(static_cast<Eigen::Index>(c)) = dt.pow(term.orders[c]).matrix();
      break;
    case TermKind::scale_factor: {
      const Eigen::ArrayXd u = s.rate.array() / sc.rate_scale_radps;
      for (std::size_t c = 0; c < term.sf_orders.size(); ++c) {
        const auto [i, j] = term.sf_orders[c];
        x.col(static_cast<Eigen::Index>(c)) = (s.rate.array() * dt.pow(i) * u.pow(j)).matrix();
      }
      break;
    }
    case TermKind::scale_factor_surface: {
      // Not-a-knot bicubic interpolation is linear in the grid values: column (i, j) is omega times the
      // surface through a unit value at node (i, j), clamped to the grid's edge outside it.
      const std::size_t nt = term.grid_temps_c.size(), nw = term.grid_rates_dps.size();
      for (std::size_t i = 0; i < nt; ++i) {
        for (std::size_t j = 0; j < nw; ++j) {
          Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nt), static_cast<Eigen::Index>(nw));
          unit(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = 1.0;
          const SplineSurface basis(term.grid_temps_c, term.grid_rates_dps, unit, OutsideGridPolicy::clamp);
          const auto col = static_cast<Eigen::Index>(i * nw + j);
          for (Eigen::Index k = 0; k < n; ++k) x(k, col) = s.rate(k) * basis(coil.temp_c(k), units::radps_to_dps(s.rate(k))).value;
        }
      }
      break;
    }
    case TermKind::shupe:
      x.col(0) = coil.rate_c_per_s;
      break;
    case TermKind::hysteresis:
      x.col(0) = thermal_branch(s, coil, sc);
      break;
    case TermKind::warmup:
      for (Eigen::Index i = 0; i < n; ++i) x(i, 0) = std::exp(-(s.t_s[static_cast<std::size_t>(i)] - t0) / term.tau_s);
      break;
    case TermKind::aging:
      for (Eigen::Index i = 0; i < n; ++i) x(i, 0) = (s.t_s[static_cast<std::size_t>(i)] - t0) / 3600.0;
      break;
    case TermKind::asymmetry:
      x.col(0) = s.rate.cwiseAbs();
      break;
    case TermKind::channel:
      for (std::size_t c = 0; c < term.channels.size(); ++c) x.col(static_cast<Eigen::Index>(c)) = s.channel(term.channels[c]);
      break;
    case TermKind::channel_squared:
      for (std::size_t c = 0; c < term.channels.size(); ++c) x.col(static_cast<Eigen::Index>(c)) = s.channel(term.channels[c]).array().square().matrix();
      break;
  }
  return x;
}

Eigen::MatrixXd design_matrix(const std::vector<Term>& terms, const Signals& s, const CoilTemperature& coil, const TermScaling& sc) {
  int cols = 0;
  for (const auto& t : terms) cols += t.size();
  Eigen::MatrixXd x(s.size(), cols);
  int at = 0;
  for (const auto& t : terms) {
    x.middleCols(at, t.size()) = term_columns(t, s, coil, sc);
    at += t.size();
  }
  return x;
}

}  // namespace gyrosid
