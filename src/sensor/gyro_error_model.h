// The deterministic part of the unified FOG model for one gyro axis (thesis eqs 3.44-3.48, after
// IEEE Std 952-1997 eq. 3.1):
//
//   omega_meas = omega + dSF(T, omega) * omega + E(T, dT/dt, f) + D_F                      (eq 3.48)
//
//   dSF(T, omega) = eps_T(T) + eps(omega) + S(T, omega) + a/2 * sign(omega)          scale-factor error
//   E             = D_T(T) + D_Tdot * dT/dt + k_g . f + f^T K_gg f                    environment terms
//   D_F           = constant bias
//
// with eps_T, eps, D_T polynomials (the classical form, thesis s3.3.2), S the bicubic surface of figs
// 3.5/3.6, a the scale-factor asymmetry, D_Tdot the Shupe coefficient (eq 3.3, fig 3.8), k_g and K_gg the
// g- and g^2-sensitivities (IEEE "acceleration-sensitive drift"). T is the coil temperature (deg C), f the
// specific force in sensor axes (z = input axis). Everything in SI: rad/s, m/s^2.
//
// forward() is eq 3.45/3.48 (simulation); inverse() solves it exactly for omega (compensation, eq 3.44)
// by safeguarded Newton, to machine precision. Random drift D_R, quantization and saturation are not
// here: see noise.h and gyro_sensor.h.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>

#include "core/polynomial.h"
#include "sensor/spline_surface.h"

namespace gyrosid {

struct GyroEnvironment {
  double temp_c = 25.0;                        // coil temperature
  double temp_rate_c_per_s = 0.0;              // its rate of change
  Eigen::Vector3d f_s = Eigen::Vector3d::Zero();  // specific force, sensor axes, m/s^2
};

struct ScaleFactorError {
  double value = 0.0;     // dSF, dimensionless
  double d_domega = 0.0;  // d(dSF)/d(omega), s/rad (away from omega = 0 for the asymmetry term)
  bool clamped = false;   // the surface was evaluated outside its grid under the clamp policy
};

struct GyroErrorModel {
  double bias_radps = 0.0;                           // D_F
  Polynomial bias_temperature_radps;                 // D_T(T), argument deg C
  Polynomial scale_factor_temperature;               // eps_T(T), argument deg C
  Polynomial scale_factor_rate;                      // eps(omega), argument rad/s
  std::optional<SplineSurface> scale_factor_surface; // S(T, omega): x = T deg C, y = omega rad/s
  double scale_factor_asymmetry = 0.0;               // dSF(omega > 0) - dSF(omega < 0)
  double shupe_rad_per_c = 0.0;                      // D_Tdot: (rad/s) per (deg C/s)
  Eigen::Vector3d g_sensitivity = Eigen::Vector3d::Zero();  // (rad/s) per (m/s^2)
  Eigen::Matrix3d g2_sensitivity = Eigen::Matrix3d::Zero(); // (rad/s) per (m/s^2)^2, symmetric

  ScaleFactorError scale_factor_error(double temp_c, double omega) const;
  double drift(const GyroEnvironment& env) const;  // E + D_F, rad/s

  // omega_meas for true rate omega (eq 3.48). `clamped` (optional) reports a surface clamp.
  double forward(double omega, const GyroEnvironment& env, bool* clamped = nullptr) const;
  // The true rate whose forward() is omega_meas (eq 3.44), to |residual| <= 1e-15 rad/s-ish.
  double inverse(double omega_meas, const GyroEnvironment& env) const;

  // Empty when the model is usable; otherwise what is wrong (e.g. a scale-factor error so large that the
  // model is not invertible: 1 + dSF + omega d(dSF)/d(omega) must stay positive).
  std::string validate(double max_rate_radps) const;
};

}  // namespace gyrosid
