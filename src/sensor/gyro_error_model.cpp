#include "sensor/gyro_error_model.h"

#include <cmath>

#include "core/error.h"

namespace gyrosid {

ScaleFactorError GyroErrorModel::scale_factor_error(double temp_c, double omega) const {
  ScaleFactorError e;
  e.value = scale_factor_temperature(temp_c) + scale_factor_rate(omega);
  e.d_domega = scale_factor_rate.derivative(omega);
  if (scale_factor_surface) {
    const SurfaceSample s = (*scale_factor_surface)(temp_c, omega);
    e.value += s.value;
    e.d_domega += s.d_dy;
    e.clamped = s.clamped;
  }
  if (omega > 0) e.value += 0.5 * scale_factor_asymmetry;
  if (omega < 0) e.value -= 0.5 * scale_factor_asymmetry;
  return e;
}

double GyroErrorModel::drift(const GyroEnvironment& env) const {
  return bias_radps + bias_temperature_radps(env.temp_c) + shupe_rad_per_c * env.temp_rate_c_per_s +
         g_sensitivity.dot(env.f_s) + env.f_s.dot(g2_sensitivity * env.f_s);
}

double GyroErrorModel::forward(double omega, const GyroEnvironment& env, bool* clamped) const {
  const ScaleFactorError sf = scale_factor_error(env.temp_c, omega);
  if (clamped) *clamped = sf.clamped;
  return omega + sf.value * omega + drift(env);
}

double GyroErrorModel::inverse(double omega_meas, const GyroEnvironment& env) const {
  // Solve phi(w) = w (1 + dSF(T, w)) + d - omega_meas = 0. phi is continuous (the asymmetry jump is
  // multiplied by w = 0) and increasing when validate() passed; Newton steps inside a bracket, bisection
  // when a step would leave it (the asymmetry kink at w = 0).
  const double target = omega_meas - drift(env);
  auto phi = [&](double w, double* slope) {
    const ScaleFactorError sf = scale_factor_error(env.temp_c, w);
    if (slope) *slope = 1.0 + sf.value + w * sf.d_domega;
    return w * (1.0 + sf.value) - target;
  };
  double w = target;
  double step = 1e-6 * (1.0 + std::abs(target));
  double lo = w, hi = w;
  // Bracket the root.
  while (phi(lo, nullptr) > 0) lo -= (step *= 2.0);
  step = 1e-6 * (1.0 + std::abs(target));
  while (phi(hi, nullptr) < 0) hi += (step *= 2.0);
  w = 0.5 * (lo + hi);
  for (int iter = 0; iter < 200; ++iter) {
    double slope = 0.0;
    const double f = phi(w, &slope);
    if (f == 0.0) return w;
    if (f < 0) lo = w;
    else hi = w;
    double next = slope > 0 ? w - f / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - w) <= 4e-16 * std::max(1.0, std::abs(w)) || hi - lo <= 4e-16 * std::max(1.0, std::abs(w))) {
      return next;
    }
    w = next;
  }
  return w;
}

std::string GyroErrorModel::validate(double max_rate_radps) const {
  // Sample the scale-factor error over the rate range at a few temperatures; the forward model must be
  // strictly increasing in omega for the inverse to exist.
  const double temps[] = {-60.0, -20.0, 0.0, 25.0, 60.0, 85.0};
  for (double t : temps) {
    for (int i = -200; i <= 200; ++i) {
      const double w = max_rate_radps * i / 200.0;
      ScaleFactorError sf;
      try {
        sf = scale_factor_error(t, w);
      } catch (const Error&) {
        continue;  // outside a surface with the error policy: not this model's operating range
      }
      const double slope = 1.0 + sf.value + w * sf.d_domega;
      if (!(slope > 0.1)) {
        return str_cat("scale-factor error too large to invert: d(omega_meas)/d(omega) = ", slope, " at T = ", t,
                       " C, omega = ", w, " rad/s");
      }
    }
  }
  if (!(std::abs(scale_factor_asymmetry) < 0.5)) return "scale_factor asymmetry must be below 0.5 (500000 ppm)";
  return "";
}

}  // namespace gyrosid
