#include "explain/effect_library.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.h"
#include "core/units.h"
#include "model/classical_model.h"
#include "model/explained_model.h"
#include "model/greybox_model.h"

namespace gyrosid::explain {

std::string_view describe(EffectId id) {
  switch (id) {
    case EffectId::temperature_bias:
      return "The bias drifts with the coil temperature beyond what the simulation's bias polynomial allows (source "
             "wavelength, coil birefringence and electronic offsets all move with temperature).";
    case EffectId::shupe:
      return "A bias proportional to the rate of change of the coil temperature (Shupe effect): a thermal gradient "
             "across the coil gives the counter-propagating waves different, time-varying optical paths.";
    case EffectId::thermal_lag:
      return "The coil temperature lags the probe's by a first-order time constant, so during ramps the errors follow "
             "a temperature the probe read earlier.";
    case EffectId::thermal_hysteresis:
      return "The bias differs between the heating and the cooling branch at the same temperature (thermal "
             "hysteresis): stresses in the coil potting and fibre jacket relax differently in each direction.";
    case EffectId::warmup_transient:
      return "An exponential drift after turn-on while the source, electronics and coil settle to their operating "
             "equilibrium (warm-up transient).";
    case EffectId::aging_trend:
      return "A slow monotonic drift of the bias over the recording, independent of temperature (ageing, long-term "
             "instability).";
    case EffectId::scale_factor_asymmetry:
      return "The scale factor differs between positive and negative rates (asymmetry), e.g. from an offset in the "
             "phase modulation or the detector.";
    case EffectId::scale_factor_nonlinearity:
      return "The scale factor varies with the rate in ways the simulation lacks (missing rate orders, including a "
             "plain scale-factor error), e.g. the sinusoidal response of an open-loop FOG.";
    case EffectId::scale_factor_temperature:
      return "The scale factor varies with temperature beyond the simulation (source wavelength and coil geometry "
             "change with temperature).";
    case EffectId::g_sensitivity:
      return "A bias proportional to the specific force along the sensor axes (g-sensitivity), from mass unbalance "
             "and strain in the coil mount.";
    case EffectId::g2_sensitivity:
      return "A bias proportional to the square of the specific force (g^2-sensitivity, anisoelasticity), from "
             "unequal compliance of the mount along different axes.";
    case EffectId::magnetic_sensitivity:
      return "A bias proportional to the magnetic field: the Faraday effect in a fibre coil, magnetic coupling into "
             "the drive or sense electronics of a MEMS gyro.";
    case EffectId::cross_axis_coupling:
      return "The gyro senses part of the rates about the other axes (cross-axis coupling: its input axis is "
             "misaligned).";
    case EffectId::auxiliary_channel:
      return "The residual follows a recorded channel that no named physics accounts for.";
  }
  return "";
}

std::string_view describe_noise(std::string_view id) {
  if (id == "white") return "angle random walk: white rate noise (photon shot noise, detector electronics); Allan slope -1/2";
  if (id == "quantization") return "quantization of the output; Allan slope -1";
  if (id == "bias_instability") return "flicker noise of the bias; the flat floor of the Allan curve";
  if (id == "gauss_markov") return "exponentially correlated bias noise; a bump in the Allan curve";
  if (id == "rate_random_walk") return "random walk of the bias; Allan slope +1/2";
  if (id == "rate_ramp") return "a steady bias ramp over the record; Allan slope +1";
  return "";
}

std::string separating_experiment(EffectId a, EffectId b) {
  using E = EffectId;
  auto is = [&](E x, E y) { return (a == x && b == y) || (a == y && b == x); };
  if (is(E::shupe, E::thermal_hysteresis)) {
    return "ramp at two or more rates (e.g. 1 and 3 C/min) with plateaus between: the Shupe bias scales with the ramp "
           "rate and vanishes on a plateau, a hysteresis offset does neither";
  }
  if (is(E::shupe, E::thermal_lag)) {
    return "ramp at one rate through several temperature ranges: a lag's bias follows the local slope of the "
           "bias-temperature curve, Shupe's does not depend on temperature; or put a second probe on the coil";
  }
  if (is(E::thermal_lag, E::thermal_hysteresis)) {
    return "hold plateaus for several lag time constants after ramps in each direction: a lag's error decays to "
           "zero, hysteresis stays";
  }
  if (is(E::warmup_transient, E::thermal_lag) || is(E::warmup_transient, E::shupe)) {
    return "power the gyro on after a soak at constant chamber temperature: a warm-up transient appears without any "
           "temperature change";
  }
  if (is(E::warmup_transient, E::aging_trend)) {
    return "record for several warm-up time constants after turn-on, or power-cycle the gyro: warm-up restarts, "
           "ageing does not";
  }
  if (is(E::scale_factor_asymmetry, E::scale_factor_nonlinearity)) {
    return "command rates of several magnitudes in both senses: asymmetry grows like |omega|, an even nonlinearity "
           "like omega^2";
  }
  if (is(E::g_sensitivity, E::temperature_bias) || is(E::g2_sensitivity, E::temperature_bias)) {
    return "change the tilt at constant temperature (a multi-position sequence on one plateau): g-sensitivity "
           "follows the tilt, a temperature bias does not";
  }
  if (is(E::warmup_transient, E::temperature_bias)) {
    return "hold the chamber at one temperature for an hour after turn-on: a warm-up transient still decays, a "
           "temperature bias does not move";
  }
  if (is(E::magnetic_sensitivity, E::temperature_bias) || is(E::magnetic_sensitivity, E::aging_trend)) {
    return "change the magnetic field at constant temperature (turn the unit in the Earth's field or drive a "
           "Helmholtz coil): a magnetic sensitivity follows the field";
  }
  if (is(E::aging_trend, E::temperature_bias)) {
    return "return to an earlier temperature later in the recording: ageing has moved on, a temperature bias "
           "returns to its value";
  }
  return "vary the two effects' inputs independently so that their regressors stop being proportional";
}

namespace {

// {lo} + the nodes strictly inside (lo, hi) farther than `gap` from both ends + {hi}.
std::vector<double> grid_within(const std::vector<double>& nodes, double lo, double hi, double gap) {
  std::vector<double> g{lo};
  for (double x : nodes) {
    if (x > lo + gap && x < hi - gap) g.push_back(x);
  }
  g.push_back(hi);
  return g;
}

}  // namespace

std::vector<Term> baseline_family(BaselineForm form, const Signals& s) {
  // Terms the data's ranges can support: temperature terms need a few degrees, scale-factor terms some rate
  // (a calibration at one temperature must not extrapolate a cubic fitted to the probe's quantisation).
  const double w_lo = units::radps_to_dps(s.rate.minCoeff()), w_hi = units::radps_to_dps(s.rate.maxCoeff());
  const double t_lo = s.temp_c.minCoeff(), t_hi = s.temp_c.maxCoeff();
  std::vector<Term> out{Term::of(TermKind::bias)};
  if (t_hi - t_lo >= 2.0) out.push_back(Term::temperature_orders({1, 2, 3}));
  if (w_hi - w_lo < 2.0) return out;
  if (form == BaselineForm::surface && w_hi - w_lo >= 40.0 && t_hi - t_lo >= 10.0) {
    // The thesis's grid (figs 3.5/3.6) with the reference sensor's -60 and 80 C rows.
    const std::vector<double> temps{-60, -20, 0, 20, 25, 40, 60, 80};
    const std::vector<double> rates{-100, -80, -60, -40, -20, -10, 10, 20, 40, 60, 80, 100};
    out.push_back(Term::surface(grid_within(temps, t_lo, t_hi, 2.0), grid_within(rates, w_lo, w_hi, 2.0)));
    return out;
  }
  Term sf = Term::of(TermKind::scale_factor);
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; j <= 3; ++j) sf.sf_orders.push_back({i, j});
  out.push_back(sf);
  return out;
}

std::vector<Term> structure_of(const CalibrationModel& model, BaselineForm form, const Signals& s, double* lag_tau_s) {
  *lag_tau_s = 0.0;
  if (const auto* e = dynamic_cast<const ExplainedModel*>(&model)) {
    *lag_tau_s = e->lag_tau_s();
    return e->terms();
  }
  std::vector<Term> out{Term::of(TermKind::bias)};
  auto orders = [](int from, int to) {
    std::vector<int> o;
    for (int k = from; k <= to; ++k) o.push_back(k);
    return o;
  };
  auto separable_sf = [](int rate_order, int temp_order) {
    Term sf = Term::of(TermKind::scale_factor);
    for (int j = 0; j <= rate_order; ++j) sf.sf_orders.push_back({0, j});
    for (int i = 1; i <= temp_order; ++i) sf.sf_orders.push_back({i, 0});
    return sf;
  };
  if (const auto* c = dynamic_cast<const ClassicalModel*>(&model)) {
    if (c->bias.size() > 1) out.push_back(Term::temperature_orders(orders(1, static_cast<int>(c->bias.size()) - 1)));
    out.push_back(separable_sf(static_cast<int>(c->sf_rate.size()) - 1, static_cast<int>(c->sf_temperature.size()) - 1));
    return out;
  }
  if (const auto* g = dynamic_cast<const GreyboxModel*>(&model)) {
    *lag_tau_s = g->lag_tau_s();
    const GyroErrorModel& e = g->errors();
    const int bias_order = static_cast<int>(e.bias_temperature_radps.coefficients.size()) - 1;
    if (bias_order >= 1) out.push_back(Term::temperature_orders(orders(1, bias_order)));
    if (e.scale_factor_surface) {
      std::vector<double> rates_dps;
      for (double w : e.scale_factor_surface->y()) rates_dps.push_back(units::radps_to_dps(w));
      out.push_back(Term::surface(e.scale_factor_surface->x(), rates_dps));
    } else {
      const int ro = std::max(0, static_cast<int>(e.scale_factor_rate.coefficients.size()) - 1);
      const int to = std::max(0, static_cast<int>(e.scale_factor_temperature.coefficients.size()) - 1);
      out.push_back(separable_sf(ro, to));
    }
    if (e.shupe_rad_per_c != 0.0) out.push_back(Term::of(TermKind::shupe));
    if (e.scale_factor_asymmetry != 0.0) out.push_back(Term::of(TermKind::asymmetry));
    if (!e.g_sensitivity.isZero()) out.push_back(Term::on_channels({"accel_x_mps2", "accel_y_mps2", "accel_z_mps2"}));
    return out;
  }
  // An RBF network (or any black box over rate and temperature) stands for a smooth 2-D error function: the
  // baseline family is what its coefficients can absorb.
  return baseline_family(form, s);
}

namespace {

std::vector<double> log_grid(double lo, double hi, int n) {
  std::vector<double> g;
  if (!(hi > lo)) return {lo};
  for (int i = 0; i < n; ++i) g.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)));
  return g;
}

Candidate candidate(EffectId id, Term term) {
  Candidate c;
  c.id = id;
  c.term = std::move(term);
  return c;
}

bool has_kind(const std::vector<Term>& base, TermKind k) {
  return std::any_of(base.begin(), base.end(), [&](const Term& t) { return t.kind == k; });
}

bool varies(const Eigen::VectorXd& v, double scale) {
  return v.size() > 1 && (v.maxCoeff() - v.minCoeff()) > scale;
}

}  // namespace

std::vector<Candidate> make_candidates(const std::vector<Term>& base, double base_lag, const ExplainInput& in,
                                       std::vector<std::string>* untestable) {
  const Signals& s = in.signals;
  std::set<int> bias_orders;
  std::set<std::pair<int, int>> sf;
  for (const auto& t : base) {
    for (int k : t.orders) bias_orders.insert(k);
    for (const auto& p : t.sf_orders) sf.insert({p[0], p[1]});
  }
  const int max_bias = bias_orders.empty() ? 0 : *bias_orders.rbegin();
  int max_j0 = -1, max_i = 0;
  for (const auto& [i, j] : sf) {
    if (i == 0) max_j0 = std::max(max_j0, j);
    max_i = std::max(max_i, i);
  }
  const double duration = s.t_s.back() - s.t_s.front();
  const bool temp_varies = varies(s.temp_c, 1.0);
  const double rate_floor = units::dps_to_radps(1.0);
  const bool rate_varies = varies(s.rate, rate_floor);
  std::vector<Candidate> out;
  auto note = [&](EffectId id, const std::string& why) { untestable->push_back(str_cat(to_string(id), ": ", why)); };

  if (temp_varies) {
    Term t = Term::of(TermKind::bias_temperature);
    for (int k : {1, 2, 3, max_bias + 1, max_bias + 2}) {
      if (k <= 6 && !bias_orders.count(k) && std::find(t.orders.begin(), t.orders.end(), k) == t.orders.end()) t.orders.push_back(k);
    }
    std::sort(t.orders.begin(), t.orders.end());
    out.push_back(candidate(EffectId::temperature_bias, t));
  } else {
    note(EffectId::temperature_bias, "the temperature does not vary");
  }

  const bool surface = has_kind(base, TermKind::scale_factor_surface);
  if (rate_varies && surface) {
    note(EffectId::scale_factor_nonlinearity, "absorbed by the simulation's scale-factor surface over (T, omega)");
    note(EffectId::scale_factor_temperature, "absorbed by the simulation's scale-factor surface over (T, omega)");
  }
  if (rate_varies) {
    Term nl = Term::of(TermKind::scale_factor);
    for (int j : {0, 1, 2, 3, max_j0 + 1, max_j0 + 2}) {
      if (j >= 0 && j <= 6 && !sf.count({0, j}) &&
          std::find_if(nl.sf_orders.begin(), nl.sf_orders.end(), [&](const auto& p) { return p[1] == j; }) == nl.sf_orders.end()) {
        nl.sf_orders.push_back({0, j});
      }
    }
    if (!nl.sf_orders.empty() && !surface) out.push_back(candidate(EffectId::scale_factor_nonlinearity, nl));
    if (temp_varies && !surface) {
      Term st = Term::of(TermKind::scale_factor);
      for (int i : {1, 2, 3, max_i + 1}) {
        for (int j = 0; j <= 2; ++j) {
          if (i <= 6 && !sf.count({i, j}) &&
              std::find(st.sf_orders.begin(), st.sf_orders.end(), std::array<int, 2>{i, j}) == st.sf_orders.end()) {
            st.sf_orders.push_back({i, j});
          }
        }
      }
      if (!st.sf_orders.empty()) out.push_back(candidate(EffectId::scale_factor_temperature, st));
    }
    const Eigen::Index positive = (s.rate.array() > rate_floor).count(), negative = (s.rate.array() < -rate_floor).count();
    if (!has_kind(base, TermKind::asymmetry)) {
      if (positive > s.size() / 20 && negative > s.size() / 20) out.push_back(candidate(EffectId::scale_factor_asymmetry, Term::of(TermKind::asymmetry)));
      else note(EffectId::scale_factor_asymmetry, "the rate does not take both signs");
    }
  } else {
    for (EffectId id : {EffectId::scale_factor_nonlinearity, EffectId::scale_factor_temperature, EffectId::scale_factor_asymmetry}) {
      note(id, "the rate does not vary");
    }
  }

  if (temp_varies) {
    if (!has_kind(base, TermKind::shupe)) out.push_back(candidate(EffectId::shupe, Term::of(TermKind::shupe)));
    const bool lag_target = std::any_of(base.begin(), base.end(), [](const Term& t) {
      return t.kind == TermKind::bias_temperature || (t.kind == TermKind::scale_factor && std::any_of(t.sf_orders.begin(), t.sf_orders.end(), [](const auto& p) { return p[0] > 0; }));
    });
    if (lag_target) {
      Candidate lag = candidate(EffectId::thermal_lag, Term::of(TermKind::bias));
      lag.nonlinear = NonlinearParameter::lag_tau;
      for (double tau : log_grid(10.0, std::clamp(duration / 4.0, 20.0, 3600.0), 12)) {
        if (std::abs(tau - base_lag) > 0.05 * tau) lag.tau_grid_s.push_back(tau);
      }
      out.push_back(lag);
    } else {
      note(EffectId::thermal_lag, "the simulation has no temperature-dependent term for a lag to act on");
    }
    const Eigen::VectorXd branch = thermal_branch(s, coil_temperature(s, base_lag), TermScaling{});
    if (!has_kind(base, TermKind::hysteresis)) {
      if ((branch.array() > 0).any() && (branch.array() < 0).any()) out.push_back(candidate(EffectId::thermal_hysteresis, Term::of(TermKind::hysteresis)));
      else note(EffectId::thermal_hysteresis, "the recording has no pair of heating and cooling branches");
    }
  } else {
    for (EffectId id : {EffectId::shupe, EffectId::thermal_lag, EffectId::thermal_hysteresis}) note(id, "the temperature does not vary");
  }

  if (!has_kind(base, TermKind::warmup)) {
    Candidate w = candidate(EffectId::warmup_transient, Term::of(TermKind::warmup));
    w.nonlinear = NonlinearParameter::warmup_tau;
    w.tau_grid_s = log_grid(std::max(30.0, 10.0 * in.dt_s), std::max(60.0, duration / 3.0), 12);
    out.push_back(w);
  }
  if (!has_kind(base, TermKind::aging)) {
    if (duration >= 600.0) out.push_back(candidate(EffectId::aging_trend, Term::of(TermKind::aging)));
    else note(EffectId::aging_trend, "the recording is shorter than 10 minutes");
  }

  auto channels = [&](const std::vector<std::string>& names, double scale) {
    std::vector<std::string> out_names;
    for (const auto& c : names) {
      const bool in_base = std::any_of(base.begin(), base.end(), [&](const Term& t) {
        return t.kind == TermKind::channel && std::find(t.channels.begin(), t.channels.end(), c) != t.channels.end();
      });
      if (!in_base && varies(s.channel(c), scale)) out_names.push_back(c);
    }
    return out_names;
  };
  const auto accel = channels(in.accel, 0.01 * units::kStandardGravity);
  if (!accel.empty()) {
    out.push_back(candidate(EffectId::g_sensitivity, Term::on_channels(accel)));
    out.push_back(candidate(EffectId::g2_sensitivity, Term::on_channels(accel, true)));
  } else {
    note(EffectId::g_sensitivity, in.accel.empty() ? "no specific force recorded" : "the specific force does not vary");
    note(EffectId::g2_sensitivity, in.accel.empty() ? "no specific force recorded" : "the specific force does not vary");
  }
  const auto mag = channels(in.magnetic, 1e-3);
  if (!mag.empty()) out.push_back(candidate(EffectId::magnetic_sensitivity, Term::on_channels(mag)));
  else note(EffectId::magnetic_sensitivity, in.magnetic.empty() ? "no magnetic channel recorded (name it mag..._ut)" : "the field does not vary");
  // Every auxiliary channel (a supply voltage, ...) on its own: not physics, but where a residual may live.
  for (const auto& aux : channels(in.aux, 0.0)) out.push_back(candidate(EffectId::auxiliary_channel, Term::on_channels({aux})));
  const auto cross = channels(in.cross_axis, rate_floor);
  if (!cross.empty()) out.push_back(candidate(EffectId::cross_axis_coupling, Term::on_channels(cross)));
  else note(EffectId::cross_axis_coupling, in.cross_axis.empty() ? "not a triad recording" : "the other axes do not turn");
  return out;
}

Eigen::MatrixXd candidate_columns(const Candidate& c, double tau, const std::vector<Term>& base, double base_lag,
                                  const Eigen::VectorXd& beta, const Signals& s, const TermScaling& scaling) {
  const CoilTemperature coil = coil_temperature(s, base_lag);
  if (c.nonlinear == NonlinearParameter::lag_tau) {
    const CoilTemperature lagged = coil_temperature(s, tau);
    return (design_matrix(base, s, lagged, scaling) - design_matrix(base, s, coil, scaling)) * beta;
  }
  Term t = c.term;
  if (c.nonlinear == NonlinearParameter::warmup_tau) t.tau_s = tau;
  return term_columns(t, s, coil, scaling);
}

}  // namespace gyrosid::explain
