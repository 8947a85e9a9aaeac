// Named physical error terms of one gyro, each a group of regressor columns along a recording - the
// vocabulary shared by the explained-physics model (model/explained_model.h) and the missing-physics
// finder (src/explain). The rate error is modelled as a linear combination of the columns:
//
//   e(t) = sum_terms sum_columns beta_c x_c(t)                                           (rad/s)
//
// with the thesis's unified model (eq 3.48) as the base - bias, bias in temperature, scale factor as a
// polynomial in (T, omega) - and the effects it left out (s3.3-3.4): Shupe (eq 3.3), hysteresis between
// heating and cooling, warm-up transient, ageing, scale-factor asymmetry, g and g^2 sensitivity, magnetic
// sensitivity and cross-axis coupling. Temperature terms use the coil temperature: the probe's through a
// first-order lag of time constant tau when a thermal lag is modelled (thesis s4.4), else the probe's.
//
// Inputs are scaled for conditioning: dT = (T - t_ref) / t_scale, u = omega / rate_scale.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"

namespace gyrosid {

enum class TermKind {
  bias,               // 1
  bias_temperature,   // dT^k for each order k
  scale_factor,       // omega dT^i u^j for each (i, j)
  scale_factor_surface,  // omega B_ij(T, omega): the bicubic-spline basis of a (T, omega) grid (thesis fig 3.6)
  shupe,              // dT_coil/dt, deg C/s
  hysteresis,         // +1/2 on the heating branch, -1/2 on the cooling branch, held through plateaus
  warmup,             // exp(-(t - t0) / tau), t0 the first sample
  aging,              // (t - t0) / 3600 s
  asymmetry,          // |omega|
  channel,            // named recorded channels as they are (specific force in g, magnetic field, other axes)
  channel_squared,    // the squares of named channels
};

template <>
struct EnumNames<TermKind> {
  static constexpr std::string_view kNoun = "physics term";
  static constexpr std::array<std::pair<TermKind, std::string_view>, 11> kTable{{{TermKind::bias, "bias"},
                                                                                {TermKind::bias_temperature, "bias_temperature"},
                                                                                {TermKind::scale_factor, "scale_factor"},
                                                                                {TermKind::scale_factor_surface, "scale_factor_surface"},
                                                                                {TermKind::shupe, "shupe"},
                                                                                {TermKind::hysteresis, "hysteresis"},
                                                                                {TermKind::warmup, "warmup"},
                                                                                {TermKind::aging, "aging"},
                                                                                {TermKind::asymmetry, "asymmetry"},
                                                                                {TermKind::channel, "channel"},
                                                                                {TermKind::channel_squared, "channel_squared"}}};
};

// The inputs the terms are built from, one gyro along a recording (SI; channels as recorded).
struct Signals {
  std::vector<double> t_s;
  Eigen::VectorXd rate;    // measured rate, rad/s
  Eigen::VectorXd temp_c;  // probe temperature
  std::map<std::string, Eigen::VectorXd> channels;

  Eigen::Index size() const { return rate.size(); }
  const Eigen::VectorXd& channel(const std::string& name) const;  // Error naming the channel when absent
};

struct TermScaling {
  double t_ref_c = 25.0, t_scale_c = 50.0;
  double rate_scale_radps = 1.0;
  // Hysteresis: the branch switches where the smoothed |dT/dt| exceeds this (deg C/s).
  double hysteresis_threshold_c_per_s = 0.05 / 60.0;
  nlohmann::json to_json() const;
  static TermScaling from_json(const nlohmann::json& j);
  static TermScaling of(const Signals& s);  // centred and scaled to the recording's range
};

struct Term {
  TermKind kind = TermKind::bias;
  std::vector<int> orders;                        // bias_temperature: powers k >= 1
  std::vector<std::array<int, 2>> sf_orders;      // scale_factor: (i, j) powers of dT and u
  std::vector<std::string> channels;              // channel, channel_squared
  std::vector<double> grid_temps_c, grid_rates_dps;  // scale_factor_surface
  double tau_s = 0.0;                             // warmup

  static Term of(TermKind kind) {
    Term t;
    t.kind = kind;
    return t;
  }
  static Term temperature_orders(std::vector<int> orders) {
    Term t = of(TermKind::bias_temperature);
    t.orders = std::move(orders);
    return t;
  }
  static Term surface(std::vector<double> temps_c, std::vector<double> rates_dps) {
    Term t = of(TermKind::scale_factor_surface);
    t.grid_temps_c = std::move(temps_c);
    t.grid_rates_dps = std::move(rates_dps);
    return t;
  }
  static Term on_channels(std::vector<std::string> channels, bool squared = false) {
    Term t = of(squared ? TermKind::channel_squared : TermKind::channel);
    t.channels = std::move(channels);
    return t;
  }

  int size() const;
  std::vector<std::string> column_names() const;
  bool uses_temperature() const {
    return kind == TermKind::bias_temperature || kind == TermKind::scale_factor || kind == TermKind::scale_factor_surface ||
           kind == TermKind::shupe;
  }
  nlohmann::json to_json() const;
  static Term from_json(const nlohmann::json& j);
};

// Coil temperature and its rate along the signals: the probe through a first-order lag (tau > 0, exact for
// the linearly interpolated probe) or the probe itself.
struct CoilTemperature {
  Eigen::VectorXd temp_c, rate_c_per_s;
};
CoilTemperature coil_temperature(const Signals& s, double lag_tau_s);

// Columns of one term (N x term.size()).
Eigen::MatrixXd term_columns(const Term& term, const Signals& s, const CoilTemperature& coil, const TermScaling& scaling);
// All terms side by side.
Eigen::MatrixXd design_matrix(const std::vector<Term>& terms, const Signals& s, const CoilTemperature& coil,
                              const TermScaling& scaling);

// The heating/cooling branch (+-1/2) the hysteresis term uses, from the smoothed probe-temperature rate.
Eigen::VectorXd thermal_branch(const Signals& s, const CoilTemperature& coil, const TermScaling& scaling);

}  // namespace gyrosid
