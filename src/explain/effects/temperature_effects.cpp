// Effects of the coil temperature beyond the simulation's: a bias drifting further with T, the Shupe bias
// (thesis eq 3.3), a thermal lag between probe and coil (s4.4), heating/cooling hysteresis.
#include <algorithm>
#include <cmath>

#include "explain/effects/effects.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain::effects {
namespace {

constexpr const char* kStaticTemperature = "the temperature does not vary";
constexpr double kSplineKnotSpacingC = 8.0;  // the bias spline's knot spacing: features of about 10 C

class TemperatureBias : public Effect {
 public:
  std::string_view id() const override { return "temperature_bias"; }
  std::string_view description() const override {
    return "The bias drifts with the coil temperature beyond what the simulation's bias polynomial allows (source "
           "wavelength, coil birefringence and electronic offsets all move with temperature).";
  }
  std::string_view parameters_help() const override {
    return "c1_dph_per_c, c2_dph_per_c2, ...: the added powers of (T - t_ref_c); t_ref_c (deg C); or, for a shape no low "
           "polynomial follows, a cubic spline in T: b3_<T>c_dph, the bias (deg/h) ((T - knot) / knot_spacing_c)^3 adds above each "
           "knot but the two outermost at each end";
  }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.temp_varies) return {{}, kStaticTemperature};
    const int max_bias = c.bias_orders.empty() ? 0 : *c.bias_orders.rbegin();
    std::vector<int> orders;
    for (int k : {1, 2, 3, max_bias + 1, max_bias + 2}) {
      if (k <= 6 && !c.bias_orders.count(k) && std::find(orders.begin(), orders.end(), k) == orders.end()) orders.push_back(k);
    }
    Proposal p;
    if (!orders.empty()) {
      std::sort(orders.begin(), orders.end());
      p.candidates.push_back(candidate(temperature_polynomial(orders)));
    }
    // A bias of any smooth shape in T, which no polynomial of low order follows (a bump, a knee): beside the
    // base's cubic, a cubic spline on knots about kSplineKnotSpacingC apart over the recorded range (at most
    // 13 knots, 9 columns).
    const Eigen::VectorXd& t = c.in.signals.temp_c;
    const double lo = t.minCoeff(), hi = t.maxCoeff();
    const int intervals = std::min(12, static_cast<int>(std::ceil((hi - lo) / kSplineKnotSpacingC)));
    if (intervals >= 4) {
      std::vector<double> knots;
      for (int i = 0; i <= intervals; ++i) knots.push_back(lo + (hi - lo) * i / intervals);
      Candidate spline = candidate(temperature_spline(knots));
      spline.flexible_form = true;
      p.candidates.push_back(std::move(spline));
    }
    if (p.candidates.empty()) {
      p.untestable = "the simulation's bias polynomial already has every order up to 6, and the temperature spans less than four "
                     "knot spacings of a spline";
    }
    return p;
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling& sc) const override {
    std::vector<PhysicalParameter> out;
    if (const auto* spline = t.as<TemperatureSpline>()) {
      // Its coefficients: the bias each knot's truncated cubic adds one knot spacing above it.
      for (std::size_t i = 2; i + 2 < spline->knots_c().size(); ++i) {
        const auto k = static_cast<Eigen::Index>(i - 2);
        out.push_back(PhysicalParameter::estimate(str_cat("b3_", std::lround(spline->knots_c()[i]), "c_dph"), beta(k), sigma(k)));
      }
      out.push_back(PhysicalParameter::reference_value("knot_spacing_c", spline->spacing_c()));
      return out;
    }
    const auto& orders = t.as<TemperaturePolynomial>()->orders();
    for (std::size_t c = 0; c < orders.size(); ++c) {
      const int k = orders[c];
      const double f = 1.0 / std::pow(sc.t_scale_c, k);
      const auto i = static_cast<Eigen::Index>(c);
      out.push_back(PhysicalParameter::estimate(k == 1 ? "c1_dph_per_c" : str_cat("c", k, "_dph_per_c", k), beta(i) * f, sigma(i) * f));
    }
    out.push_back(PhysicalParameter::reference_value("t_ref_c", sc.t_ref_c));
    return out;
  }
};

class Shupe : public Effect {
 public:
  std::string_view id() const override { return "shupe"; }
  std::string_view description() const override {
    return "A bias proportional to the rate of change of the coil temperature (Shupe effect): a thermal gradient "
           "across the coil gives the counter-propagating waves different, time-varying optical paths.";
  }
  std::string_view parameters_help() const override {
    return "k_dph_per_cpm: bias per coil-temperature rate, (deg/h) per (deg C/min); gradient_tau_s: where the coil's gradient "
           "relaxes visibly, its diffusion time constant (s)";
  }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.temp_varies) return {{}, kStaticTemperature};
    if (c.base_has<ShupeTerm>()) return {};
    return {{candidate(shupe_term())}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    const double tau = t.as<ShupeTerm>()->gradient_tau_s();
    if (tau == 0.0) return {PhysicalParameter::estimate("k_dph_per_cpm", beta(0) / 60.0, sigma(0) / 60.0)};
    return {PhysicalParameter::estimate("k_dph_per_cpm", beta(0) / 60.0, sigma(0) / 60.0), PhysicalParameter::reference_value("gradient_tau_s", tau)};
  }
  // The gradient's diffusion time constant (term_kinds.h, ShupeTerm): the rate form is its limit for slow
  // changes, and a coil whose core lags its outer layers by 400 s (the third generator's gradient Shupe)
  // was named Shupe with a thermal lag of 350-390 s beside it, the lag lending the rate its delay. On a grid
  // from half a minute (ten samples at least) to two hours.
  std::vector<Term> richer_forms(const Term& selected, const ExplainInput& in) const override {
    const auto* s = selected.as<ShupeTerm>();
    if (!s || s->gradient_tau_s() > 0) return {};
    std::vector<Term> out;
    for (double tau : log_grid(std::max(30.0, 10.0 * in.dt_s), 7200.0, 12)) out.push_back(shupe_term(tau));
    return out;
  }
  std::string separating_experiment(std::string_view other) const override {
    if (other == "thermal_hysteresis") {
      return "ramp at two or more rates (e.g. 1 and 3 C/min) with plateaus between: the Shupe bias scales with the ramp "
             "rate and vanishes on a plateau, a hysteresis offset does neither";
    }
    if (other == "thermal_lag") {
      return "ramp at one rate through several temperature ranges: a lag's bias follows the local slope of the "
             "bias-temperature curve, Shupe's does not depend on temperature; or put a second probe on the coil";
    }
    return "";
  }
};

// The coil lags the probe by tau: one column, the change of the model's prediction (its coefficients) when
// the coil lags by tau instead of the base's lag - the Gauss-Newton direction of the one-parameter lag
// model, not a free re-fit of every temperature column.
class ThermalLag : public Effect {
 public:
  std::string_view id() const override { return "thermal_lag"; }
  std::string_view description() const override {
    return "The coil temperature lags the probe's by a first-order time constant, so during ramps the errors follow "
           "a temperature the probe read earlier.";
  }
  std::string_view parameters_help() const override { return "tau_s: the first-order time constant from probe to coil (s)"; }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.temp_varies) return {{}, kStaticTemperature};
    const bool target = std::any_of(c.base.begin(), c.base.end(), [](const Term& t) {
      const auto* sf = t.as<ScaleFactorPolynomial>();
      return t.as<TemperaturePolynomial>() ||
             (sf && std::any_of(sf->orders().begin(), sf->orders().end(), [](const auto& p) { return p[0] > 0; }));
    });
    if (!target) return {{}, "the simulation has no temperature-dependent term for a lag to act on"};
    Candidate lag;
    lag.effect = this;
    lag.nonlinear = NonlinearParameter::coil_lag;
    for (double tau : log_grid(10.0, std::clamp(c.duration_s / 4.0, 20.0, 3600.0), 12)) {
      if (std::abs(tau - c.base_lag_tau_s) > 0.05 * tau) lag.tau_grid_s.push_back(tau);
    }
    return {{lag}, ""};
  }
  Eigen::MatrixXd columns(const Candidate&, double tau_s, const ModelColumns& m) const override {
    const CoilTemperature coil = coil_temperature(m.signals, m.lag_tau_s), lagged = coil_temperature(m.signals, tau_s);
    return (design_matrix(m.terms, m.signals, lagged, m.scaling) - design_matrix(m.terms, m.signals, coil, m.scaling)) * m.beta;
  }
  std::string separating_experiment(std::string_view other) const override {
    if (other == "thermal_hysteresis") {
      return "hold plateaus for several lag time constants after ramps in each direction: a lag's error decays to "
             "zero, hysteresis stays";
    }
    return "";
  }
};

class ThermalHysteresis : public Effect {
 public:
  std::string_view id() const override { return "thermal_hysteresis"; }
  std::string_view description() const override {
    return "The bias differs between the heating and the cooling branch at the same temperature (thermal "
           "hysteresis): stresses in the coil potting and fibre jacket relax differently in each direction.";
  }
  std::string_view parameters_help() const override {
    return "offset_dph: heating-branch bias minus cooling-branch bias (deg/h); width_c: temperature travel over which the bias moves "
           "between the branches after a reversal (C); a loop of two widths adds second_width_c and second_offset_dph, the second "
           "play's share of offset_dph";
  }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.temp_varies) return {{}, kStaticTemperature};
    if (c.base_has<HysteresisTerm>()) return {};
    const Eigen::VectorXd branch = thermal_branch(c.in.signals, coil_temperature(c.in.signals, c.base_lag_tau_s), TermScaling{});
    if (!((branch.array() > 0).any() && (branch.array() < 0).any())) return {{}, "the recording has no pair of heating and cooling branches"};
    Candidate h = candidate(hysteresis_term(0.2));
    h.nonlinear = NonlinearParameter::term_parameter;
    h.tau_grid_s = width_grid(c.in.signals);
    return {{h}, ""};
  }
  // A loop of two widths (two plays side by side, a Prandtl-Ishlinskii loop): reversals inside the range
  // (minor loops) show a loop's inner shape, which one play of one width cannot follow - on the independent
  // generator's minor-loop programme one play left 7-9 % of a two-width loop's held-out excess and its offset
  // 18 % off. The second width on a finer grid over the same range, at least 1.5x from the first.
  std::vector<Term> richer_forms(const Term& selected, const ExplainInput& in) const override {
    const auto* h = selected.as<HysteresisTerm>();
    const auto width = selected.parameter();
    if (!h || !width || h->second_width_c() > 0) return {};
    std::vector<Term> out;
    const std::vector<double> grid = width_grid(in.signals);
    for (double w : log_grid(0.5 * grid.front(), grid.back(), 16)) {
      if (std::max(w, width->value) > 1.5 * std::min(w, width->value)) out.push_back(hysteresis_term(width->value, w));
    }
    return out;
  }
  // The loop's height is the sum of the plays' coefficients. Its sd is from the per-column sds as if they
  // were independent: the two plays' columns are positively correlated, their coefficients negatively, so
  // this overstates it (a conservative interval).
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    if (t.size() == 1) return {PhysicalParameter::estimate("offset_dph", beta(0), sigma(0))};
    return {PhysicalParameter::estimate("offset_dph", beta.sum(), sigma.norm()),
            PhysicalParameter::estimate("second_offset_dph", beta(1), sigma(1)),
            PhysicalParameter::reference_value("second_width_c", t.as<HysteresisTerm>()->second_width_c())};
  }

 private:
  // The transition width between the branches, from a nearly sharp switch to a slow relaxation.
  static std::vector<double> width_grid(const Signals& s) {
    const double range = s.temp_c.maxCoeff() - s.temp_c.minCoeff();
    return log_grid(0.2, std::clamp(0.5 * range, 0.4, 20.0), 8);
  }
};

}  // namespace

std::unique_ptr<Effect> temperature_bias() { return std::make_unique<TemperatureBias>(); }
std::unique_ptr<Effect> shupe() { return std::make_unique<Shupe>(); }
std::unique_ptr<Effect> thermal_lag() { return std::make_unique<ThermalLag>(); }
std::unique_ptr<Effect> thermal_hysteresis() { return std::make_unique<ThermalHysteresis>(); }

}  // namespace gyrosid::explain::effects
