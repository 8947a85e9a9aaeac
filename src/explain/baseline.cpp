#include "explain/baseline.h"

#include <algorithm>

#include "core/error.h"
#include "core/units.h"
#include "model/classical_model.h"
#include "model/explained_model.h"
#include "model/greybox_model.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {
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

std::vector<int> orders(int from, int to) {
  std::vector<int> o;
  for (int k = from; k <= to; ++k) o.push_back(k);
  return o;
}

// omega u^j for j <= rate_order and omega dT^i for 1 <= i <= temp_order: the classical separable form.
Term separable_scale_factor(int rate_order, int temp_order) {
  ScaleFactorPolynomial::Orders sf;
  for (int j = 0; j <= rate_order; ++j) sf.push_back({0, j});
  for (int i = 1; i <= temp_order; ++i) sf.push_back({i, 0});
  return scale_factor_polynomial(sf);
}

std::vector<Term> greybox_structure(const GreyboxModel& g) {
  std::vector<Term> out{bias_term()};
  const GyroErrorModel& e = g.errors();
  const int bias_order = static_cast<int>(e.bias_temperature_radps.coefficients.size()) - 1;
  if (bias_order >= 1) out.push_back(temperature_polynomial(orders(1, bias_order)));
  if (e.scale_factor_surface) {
    std::vector<double> rates_dps;
    for (double w : e.scale_factor_surface->y()) rates_dps.push_back(units::radps_to_dps(w));
    out.push_back(scale_factor_surface(e.scale_factor_surface->x(), rates_dps));
  } else {
    const int ro = std::max(0, static_cast<int>(e.scale_factor_rate.coefficients.size()) - 1);
    const int to = std::max(0, static_cast<int>(e.scale_factor_temperature.coefficients.size()) - 1);
    out.push_back(separable_scale_factor(ro, to));
  }
  if (e.shupe_rad_per_c != 0.0) out.push_back(shupe_term());
  if (e.scale_factor_asymmetry != 0.0) out.push_back(asymmetry_term());
  if (!e.g_sensitivity.isZero()) out.push_back(channel_term({"accel_x_mps2", "accel_y_mps2", "accel_z_mps2"}));
  return out;
}

}  // namespace

std::vector<Term> baseline_family(BaselineForm form, const Signals& s) {
  if (form == BaselineForm::automatic) fail("explain: the baseline form 'auto' is resolved before the family is built");
  const double w_lo = units::radps_to_dps(s.rate.minCoeff()), w_hi = units::radps_to_dps(s.rate.maxCoeff());
  const double t_lo = s.temp_c.minCoeff(), t_hi = s.temp_c.maxCoeff();
  std::vector<Term> out{bias_term()};
  if (t_hi - t_lo >= 2.0) out.push_back(temperature_polynomial({1, 2, 3}));
  if (w_hi - w_lo < 2.0) return out;
  if (form == BaselineForm::surface && w_hi - w_lo >= 40.0 && t_hi - t_lo >= 10.0) {
    // The thesis's grid (figs 3.5/3.6) with the reference sensor's -60 and 80 C rows.
    const std::vector<double> temps{-60, -20, 0, 20, 25, 40, 60, 80};
    const std::vector<double> rates{-100, -80, -60, -40, -20, -10, 10, 20, 40, 60, 80, 100};
    out.push_back(scale_factor_surface(grid_within(temps, t_lo, t_hi, 2.0), grid_within(rates, w_lo, w_hi, 2.0)));
    return out;
  }
  ScaleFactorPolynomial::Orders sf;
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; j <= 3; ++j) sf.push_back({i, j});
  out.push_back(scale_factor_polynomial(sf));
  return out;
}

std::optional<std::vector<Term>> structure_of(const CalibrationModel& model, double* lag_tau_s) {
  *lag_tau_s = 0.0;
  if (const auto* e = dynamic_cast<const ExplainedModel*>(&model)) {
    *lag_tau_s = e->lag_tau_s();
    return e->terms();
  }
  if (const auto* c = dynamic_cast<const ClassicalModel*>(&model)) {
    std::vector<Term> out{bias_term()};
    if (c->bias.size() > 1) out.push_back(temperature_polynomial(orders(1, static_cast<int>(c->bias.size()) - 1)));
    out.push_back(separable_scale_factor(static_cast<int>(c->sf_rate.size()) - 1, static_cast<int>(c->sf_temperature.size()) - 1));
    return out;
  }
  if (const auto* g = dynamic_cast<const GreyboxModel*>(&model)) {
    *lag_tau_s = g->lag_tau_s();
    return greybox_structure(*g);
  }
  // An RBF network (or any black box over rate and temperature) stands for a smooth 2-D error function: the
  // baseline family is what its coefficients can absorb.
  return std::nullopt;
}

}  // namespace gyrosid::explain
