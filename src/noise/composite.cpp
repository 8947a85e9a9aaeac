#include "noise/composite.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/format.h"
#include "noise/processes.h"

namespace gyrosid {

double CompositeNoise::allan_variance(double tau) const {
  double v = 3.0 * point_variance() / (tau * tau) + white * white / tau + kFlickerAllanFactor * flicker * flicker +
             random_walk * random_walk * tau / 3.0 + ramp * ramp * tau * tau / 2.0;
  for (const auto& gm : gauss_markov) v += gauss_markov_allan_variance(gm.sigma, gm.tau_s, tau);
  return v;
}

double CompositeNoise::phase_covariance(double h) const {
  const double a = std::abs(h);
  double c = -white * white * a / 2.0 + random_walk * random_walk * a * a * a / 12.0;
  if (flicker > 0 && a > 0) c += flicker * flicker * h * h * std::log(a) / (2.0 * std::numbers::pi);
  for (const auto& gm : gauss_markov) {
    const double r = a / gm.tau_s;
    // r - 1 + e^{-r}, by its series where the difference cancels.
    const double shape = r < 1e-3 ? r * r / 2.0 - r * r * r / 6.0 : r - 1.0 + std::exp(-r);
    c -= gm.sigma * gm.sigma * gm.tau_s * gm.tau_s * shape;
  }
  return c;
}

std::string CompositeNoise::describe(const std::string& unit) const {
  std::string out;
  auto add = [&](const std::string& text) { out += (out.empty() ? "" : ", ") + text; };
  if (quantization > 0) add(str_cat("Q ", format_significant(quantization, 3), " ", unit, " s"));
  if (filter > 0) add(str_cat("F ", format_significant(filter, 3), " ", unit, " s"));
  if (white > 0) add(str_cat("N ", format_significant(white, 3), " ", unit, " sqrt(s)"));
  if (flicker > 0) add(str_cat("B ", format_significant(flicker, 3), " ", unit));
  if (random_walk > 0) add(str_cat("K ", format_significant(random_walk, 3), " ", unit, "/sqrt(s)"));
  if (ramp != 0) add(str_cat("R ", format_significant(ramp, 3), " ", unit, "/s"));
  for (const auto& gm : gauss_markov) {
    add(str_cat("Gauss-Markov (sigma ", format_significant(gm.sigma, 3), " ", unit, ", tau ", format_significant(gm.tau_s, 3), " s)"));
  }
  return out.empty() ? "none" : out;
}

CompositeNoise CompositeNoise::scaled(double factor) const {
  CompositeNoise c = *this;
  for (double* v : {&c.quantization, &c.filter, &c.white, &c.flicker, &c.random_walk, &c.ramp}) *v *= factor;
  for (auto& gm : c.gauss_markov) gm.sigma *= factor;
  return c;
}

NoiseOptions noise_options_of(const CompositeNoise& m, std::string* left_out) {
  NoiseOptions o;
  o.arw_rad_rt_s = m.white;
  o.bias_instability_radps = m.flicker;
  o.rrw_rad_s_rt_s = m.random_walk;
  o.rate_ramp_radps2 = m.ramp;
  for (const auto& gm : m.gauss_markov) o.gauss_markov.push_back({gm.sigma, gm.tau_s});
  if (left_out) {
    *left_out = m.quantization > 0 || m.filter > 0 ? "the quantization and filter terms (they act at the shortest taus only)" : "";
  }
  return o;
}

}  // namespace gyrosid
