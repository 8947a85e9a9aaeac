// Every physics-term kind in one registry: its name (the "kind" of a term in a model file), what its columns
// are, and its loader from the term's JSON fields.
#include "model/terms/term_kinds.h"

#include <cmath>

#include "core/error.h"

namespace gyrosid {
namespace {

template <typename T>
std::vector<T> list(const nlohmann::json& j, const char* key) {
  return j.at(key).get<std::vector<T>>();
}

// A polynomial order from a model file: a whole number in [0, kMaxOrder] (found by fuzzing: nlohmann converts
// 1.8e86 to int with undefined behaviour, and pow(dT, 1e9) is no model).
constexpr int kMaxOrder = 12;
int order(const nlohmann::json& j, const char* key) {
  const double v = j.is_number() ? j.get<double>() : -1.0;
  if (!(v >= 0 && v <= kMaxOrder) || v != std::floor(v)) fail("physics term: '", key, "' holds ", j.dump(), "; expected whole orders from 0 to ", kMaxOrder);
  return static_cast<int>(v);
}

std::vector<int> orders(const nlohmann::json& j, const char* key) {
  std::vector<int> out;
  for (const auto& v : j.at(key)) out.push_back(order(v, key));
  return out;
}

std::vector<std::array<int, 2>> order_pairs(const nlohmann::json& j, const char* key) {
  std::vector<std::array<int, 2>> out;
  for (const auto& v : j.at(key)) {
    if (!v.is_array() || v.size() != 2) fail("physics term: '", key, "' holds ", v.dump(), "; expected pairs [i, j] of orders");
    out.push_back({order(v[0], key), order(v[1], key)});
  }
  return out;
}

}  // namespace

const TermKindRegistry& term_kinds() {
  static const TermKindRegistry registry = [] {
    TermKindRegistry r("physics term");
    auto none = [] { return std::string(); };
    using P = std::unique_ptr<TermBasis>;
    r.add({"bias", "a constant", none, [](const nlohmann::json&) -> P { return std::make_unique<BiasTerm>(); }})
        .add({"bias_temperature", "dT^k for each order k (bias polynomial in the coil temperature)", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<TemperaturePolynomial>(orders(j, "orders")); }})
        .add({"scale_factor", "omega dT^i u^j for each (i, j) (scale-factor polynomial)", none,
              [](const nlohmann::json& j) -> P {
                return std::make_unique<ScaleFactorPolynomial>(order_pairs(j, "sf_orders"));
              }})
        .add({"scale_factor_surface", "omega B_ij(T, omega): bicubic-spline scale-factor surface on a (T, omega) grid", none,
              [](const nlohmann::json& j) -> P {
                const auto& g = j.at("grid");
                return std::make_unique<ScaleFactorSurface>(list<double>(g, "temperatures_c"), list<double>(g, "rates_dps"));
              }})
        .add({"bias_temperature_spline", "((T - k_i)+ / h)^3 at knots_c but the two outermost at each end (spacing h): beside a cubic bias, the not-a-knot cubic splines in the coil temperature", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<TemperatureSpline>(list<double>(j, "knots_c")); }})
        .add({"shupe", "dT_coil/dt, deg C/s (with gradient_tau_s, the rate of T_coil through a first-order lag of that time constant)", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<ShupeTerm>(j.value("gradient_tau_s", 0.0)); }})
        .add({"hysteresis", "+-1/2 on the heating/cooling branch, moving between them over width_c after a reversal (and a second "
                            "column over second_width_c, if given)", none,
              [](const nlohmann::json& j) -> P {
                return std::make_unique<HysteresisTerm>(j.value("width_c", 0.0), j.value("second_width_c", 0.0));
              }})
        .add({"warmup", "exp(-(t - t0) / tau)", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<WarmupTerm>(j.value("tau_s", 0.0)); }})
        .add({"aging", "(t - t0) / 1 h", none, [](const nlohmann::json&) -> P { return std::make_unique<AgingTerm>(); }})
        .add({"aging_log", "(tau_s / 1 h) ln(1 + (t - t0) / tau_s): ageing that slows, slope 1/h at t0", none,
              [](const nlohmann::json& j) -> P {
                const double tau = j.at("tau_s").get<double>();
                if (!(tau > 0)) fail("physics term aging_log: tau_s must be positive");
                return std::make_unique<AgingTerm>(tau);
              }})
        .add({"bias_step", "1 from t_s on: a change point of the bias (and exp(-(t - t_s) / recovery_tau_s) from t_s on, if given: "
                           "a step that partly recovers)", none,
              [](const nlohmann::json& j) -> P {
                return std::make_unique<ChangeTerm>(j.at("t_s").get<double>(), false, j.value("recovery_tau_s", 0.0));
              }})
        .add({"bias_ramp", "(t - t_s) / 1 h from t_s on: a trend starting at t_s (and its square, if curved: true)", none,
              [](const nlohmann::json& j) -> P {
                return std::make_unique<ChangeTerm>(j.at("t_s").get<double>(), true, 0.0, j.value("curved", false));
              }})
        .add({"asymmetry", "|omega|", none, [](const nlohmann::json&) -> P { return std::make_unique<AsymmetryTerm>(); }})
        .add({"channel", "recorded channels as they are", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<ChannelTerm>(list<std::string>(j, "channels"), false); }})
        .add({"channel_squared", "squares of recorded channels", none,
              [](const nlohmann::json& j) -> P { return std::make_unique<ChannelTerm>(list<std::string>(j, "channels"), true); }});
    return r;
  }();
  return registry;
}

}  // namespace gyrosid
