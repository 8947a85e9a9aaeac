// Effects on the scale factor beyond the simulation's: asymmetry between the senses, missing rate orders
// (nonlinearity), a variation with temperature.
#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "explain/effects/effects.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain::effects {
namespace {

constexpr const char* kStaticRate = "the rate does not vary";
constexpr const char* kAbsorbed = "absorbed by the simulation's scale-factor surface over (T, omega)";

// k_u<j>_ppm for the rate orders, k_t<i>_u<j>_ppm_per_c<i> for the temperature ones, at the scaling's
// reference temperature and rate scale.
std::vector<PhysicalParameter> polynomial_parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                                     const TermScaling& sc) {
  std::vector<PhysicalParameter> out;
  const auto& orders = t.as<ScaleFactorPolynomial>()->orders();
  for (std::size_t c = 0; c < orders.size(); ++c) {
    const auto [i, j] = orders[c];
    const double f = 1e6 * kDphPerRadps / std::pow(sc.t_scale_c, i);
    const std::string name = i == 0 ? str_cat("k_u", j, "_ppm") : str_cat("k_t", i, "_u", j, i == 1 ? "_ppm_per_c" : str_cat("_ppm_per_c", i));
    const auto k = static_cast<Eigen::Index>(c);
    out.push_back(PhysicalParameter::estimate(name, beta(k) * f, sigma(k) * f));
  }
  out.push_back(PhysicalParameter::reference_value("rate_scale_dps", units::radps_to_dps(sc.rate_scale_radps)));
  out.push_back(PhysicalParameter::reference_value("t_ref_c", sc.t_ref_c));
  return out;
}

bool has_order(const ScaleFactorPolynomial::Orders& orders, std::array<int, 2> o) {
  return std::find(orders.begin(), orders.end(), o) != orders.end();
}

class Asymmetry : public Effect {
 public:
  std::string_view id() const override { return "scale_factor_asymmetry"; }
  std::string_view description() const override {
    return "The scale factor differs between positive and negative rates (asymmetry), e.g. from an offset in the "
           "phase modulation or the detector.";
  }
  std::string_view parameters_help() const override { return "asymmetry_ppm: scale factor at positive minus at negative rates (ppm)"; }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.rate_varies) return {{}, kStaticRate};
    if (c.base_has<AsymmetryTerm>()) return {};
    const Eigen::VectorXd& w = c.in.signals.rate;
    const double floor = units::dps_to_radps(1.0);
    const Eigen::Index positive = (w.array() > floor).count(), negative = (w.array() < -floor).count();
    if (!(positive > w.size() / 20 && negative > w.size() / 20)) return {{}, "the rate does not take both signs"};
    return {{candidate(asymmetry_term())}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term&, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    return {PhysicalParameter::estimate("asymmetry_ppm", 2e6 * beta(0) * kDphPerRadps, 2e6 * sigma(0) * kDphPerRadps)};
  }
  std::string separating_experiment(std::string_view other) const override {
    if (other == "scale_factor_nonlinearity") {
      return "command rates of several magnitudes in both senses: asymmetry grows like |omega|, an even nonlinearity "
             "like omega^2";
    }
    if (other == "scale_factor_surface" || other == "scale_factor_polynomial") {
      return "hold rates of a few deg/s in both senses (and reverse slowly through zero) beside the calibrated ones: a "
             "scale factor that steps between the senses puts a kink in the error at zero rate, which a smooth scale "
             "factor over the rate cannot follow";
    }
    return "";
  }
  // Tested against a smooth scale factor of rate order 2. It keeps omega u (an error in omega^2, a FOG's
  // ordinary second-order term) and drops omega u^3: with it, an error in omega^4, the two even terms bend
  // to follow |omega| over a wide span of rates and would absorb the asymmetry they are tested against.
  int core_rate_order() const override { return 2; }
};

class Nonlinearity : public Effect {
 public:
  std::string_view id() const override { return "scale_factor_nonlinearity"; }
  std::string_view description() const override {
    return "The scale factor varies with the rate in ways the simulation lacks (missing rate orders, including a "
           "plain scale-factor error), e.g. the sinusoidal response of an open-loop FOG.";
  }
  std::string_view parameters_help() const override { return "k_u<j>_ppm: scale-factor error per (omega / rate_scale_dps)^j (ppm)"; }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.rate_varies) return {{}, kStaticRate};
    if (c.base_has<ScaleFactorSurface>()) return {{}, kAbsorbed};
    int max_j0 = -1;
    for (const auto& [i, j] : c.sf_orders) {
      if (i == 0) max_j0 = std::max(max_j0, j);
    }
    ScaleFactorPolynomial::Orders orders;
    for (int j : {0, 1, 2, 3, max_j0 + 1, max_j0 + 2}) {
      const bool listed = std::any_of(orders.begin(), orders.end(), [&](const auto& p) { return p[1] == j; });
      if (j >= 0 && j <= 6 && !c.sf_orders.count({0, j}) && !listed) orders.push_back({0, j});
    }
    if (orders.empty()) return {};
    return {{candidate(scale_factor_polynomial(orders))}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling& sc) const override {
    return polynomial_parameters(t, beta, sigma, sc);
  }
};

class TemperatureScaleFactor : public Effect {
 public:
  std::string_view id() const override { return "scale_factor_temperature"; }
  std::string_view description() const override {
    return "The scale factor varies with temperature beyond the simulation (source wavelength and coil geometry "
           "change with temperature).";
  }
  std::string_view parameters_help() const override {
    return "k_t<i>_u<j>_ppm_per_c<i>: scale-factor error per (T - t_ref_c)^i (omega / rate_scale_dps)^j";
  }
  Proposal propose(const CandidateContext& c) const override {
    if (!c.rate_varies) return {{}, kStaticRate};
    if (c.base_has<ScaleFactorSurface>()) return {{}, kAbsorbed};
    if (!c.temp_varies) return {};
    int max_i = 0;
    for (const auto& [i, j] : c.sf_orders) max_i = std::max(max_i, i);
    ScaleFactorPolynomial::Orders orders;
    for (int i : {1, 2, 3, max_i + 1}) {
      for (int j = 0; j <= 2; ++j) {
        if (i <= 6 && !c.sf_orders.count({i, j}) && !has_order(orders, {i, j})) orders.push_back({i, j});
      }
    }
    if (orders.empty()) return {};
    return {{candidate(scale_factor_polynomial(orders))}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling& sc) const override {
    return polynomial_parameters(t, beta, sigma, sc);
  }
};

}  // namespace

std::unique_ptr<Effect> scale_factor_asymmetry() { return std::make_unique<Asymmetry>(); }
std::unique_ptr<Effect> scale_factor_nonlinearity() { return std::make_unique<Nonlinearity>(); }
std::unique_ptr<Effect> scale_factor_temperature() { return std::make_unique<TemperatureScaleFactor>(); }

}  // namespace gyrosid::explain::effects
