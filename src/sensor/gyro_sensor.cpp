#include "sensor/gyro_sensor.h"

#include <cmath>

#include "core/error.h"
#include "core/triad_axes.h"

namespace gyrosid {

std::string ThermalPath::validate() const {
  if (!(delay_s >= 0)) return str_cat("thermal.delay_s = ", delay_s, " must be >= 0");
  if (!(tau_s >= 0)) return str_cat("thermal.tau_s = ", tau_s, " must be >= 0");
  if (!(coil_tau_s >= 0)) return str_cat("thermal.coil_tau_s = ", coil_tau_s, " must be >= 0");
  return "";
}

std::string GyroSensor::validate() const {
  if (!(quantization_rad >= 0)) return "quantization must be >= 0";
  if (!(range_radps > 0)) return "range must be > 0";
  if (auto p = noise.validate(); !p.empty()) return p;
  if (auto p = thermal.validate(); !p.empty()) return p;
  const double check_range = std::isfinite(range_radps) ? range_radps : 20.0;
  return errors.validate(check_range);
}

std::string TriadSensor::validate() const {
  for (int i = 0; i < 3; ++i) {
    if (auto p = gyros[i].validate(); !p.empty()) return str_cat("gyro ", kTriadAxes[i], ": ", p);
  }
  return thermal.validate();
}

GyroOutput simulate_gyro(const GyroSensor& sensor, const Excitation& ex, const Eigen::Matrix3d& c_s_b,
                         std::uint64_t seed, const std::string& stream) {
  const std::size_t n = ex.size();
  GyroOutput out;
  out.rate_radps.resize(n);
  NoiseGenerator noise(sensor.noise, seed, stream);
  const Eigen::Vector3d input_axis = c_s_b.row(2).transpose();
  double theta = 0.0;
  double pulses_prev = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double dt = k > 0 ? ex.t_s[k] - ex.t_s[k - 1] : (n > 1 ? ex.t_s[1] - ex.t_s[0] : 1.0);
    GyroEnvironment env;
    env.temp_c = ex.coil_temp_c[k];
    env.temp_rate_c_per_s = ex.coil_temp_rate_c_per_s[k];
    env.f_s = c_s_b * ex.f_b[k];
    bool clamped = false;
    double w = sensor.errors.forward(input_axis.dot(ex.omega_ib_b[k]), env, &clamped);
    if (clamped) ++out.clamped_samples;
    if (sensor.noise.any()) w += noise.next(ex.t_s[k], dt);
    if (std::abs(w) > sensor.range_radps) {
      w = std::copysign(sensor.range_radps, w);
      ++out.saturated_samples;
    }
    if (sensor.quantization_rad > 0) {
      theta += w * dt;
      const double pulses = std::floor(theta / sensor.quantization_rad);
      w = (pulses - pulses_prev) * sensor.quantization_rad / dt;
      pulses_prev = pulses;
    }
    out.rate_radps[k] = w;
  }
  return out;
}

GyroOutput simulate_single(const GyroSensor& sensor, const Excitation& excitation, std::uint64_t seed) {
  return simulate_gyro(sensor, excitation, Eigen::Matrix3d::Identity(), seed, "gyro");
}

TriadOutput simulate_triad(const TriadSensor& sensor, const Excitation& excitation, std::uint64_t seed) {
  TriadOutput out;
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z"};
  for (int i = 0; i < 3; ++i) {
    const Eigen::Matrix3d c_s_b = body_from_ia(i, sensor.alignment[i]).transpose();
    out.gyro[i] = simulate_gyro(sensor.gyros[i], excitation, c_s_b, seed, names[i]);
  }
  return out;
}

}  // namespace gyrosid
