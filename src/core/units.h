// Unit conversions used at the edges (configs, recordings, reports). Internally gyrosid is SI
// (rad, rad/s, s, m, m/s^2) with temperature in degrees Celsius.
#pragma once

#include <numbers>

namespace gyrosid::units {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDegToRad = kPi / 180.0;
inline constexpr double kRadToDeg = 180.0 / kPi;
inline constexpr double kSecondsPerHour = 3600.0;
inline constexpr double kSecondsPerMinute = 60.0;
inline constexpr double kStandardGravity = 9.80665;  // m/s^2, for "g" units (IEEE Std 528)
inline constexpr double kArcsecToRad = kDegToRad / 3600.0;

constexpr double deg_to_rad(double deg) { return deg * kDegToRad; }
constexpr double rad_to_deg(double rad) { return rad * kRadToDeg; }

// Rates.
constexpr double dps_to_radps(double dps) { return dps * kDegToRad; }
constexpr double radps_to_dps(double radps) { return radps * kRadToDeg; }
constexpr double dph_to_radps(double dph) { return dph * kDegToRad / kSecondsPerHour; }
constexpr double radps_to_dph(double radps) { return radps * kRadToDeg * kSecondsPerHour; }

// Noise densities. Angle random walk N in deg/sqrt(h) -> rad/sqrt(s); rate random walk K in
// (deg/h)/sqrt(h) -> rad/s/sqrt(s); rate ramp R in (deg/h)/h -> rad/s^2.
constexpr double deg_rt_h_to_rad_rt_s(double n) { return n * kDegToRad / 60.0; }
constexpr double rad_rt_s_to_deg_rt_h(double n) { return n * kRadToDeg * 60.0; }
constexpr double dph_rt_h_to_rad_s_rt_s(double k) { return dph_to_radps(k) / 60.0; }
constexpr double rad_s_rt_s_to_dph_rt_h(double k) { return radps_to_dph(k) * 60.0; }
constexpr double dph_per_h_to_radps2(double r) { return dph_to_radps(r) / kSecondsPerHour; }
constexpr double radps2_to_dph_per_h(double r) { return radps_to_dph(r) * kSecondsPerHour; }

// Dimensionless ratios.
constexpr double ppm_to_ratio(double ppm) { return ppm * 1e-6; }
constexpr double ratio_to_ppm(double ratio) { return ratio * 1e6; }

// Temperature rate.
constexpr double c_per_min_to_c_per_s(double r) { return r / kSecondsPerMinute; }
constexpr double c_per_s_to_c_per_min(double r) { return r * kSecondsPerMinute; }

}  // namespace gyrosid::units
