// A simulated gyro: the deterministic error model, its random drift, output quantization and range
// saturation, and the thermal path from chamber to coil - and a triad of three of them with misalignment.
//
// Output pipeline per sample k (rates in rad/s):
//   w_k   = omega_in,k (1 + dSF) + E + D_F + D_R,k             error model (eq 3.48) + noise (eq 3.5)
//   w_k   = clip(w_k, -range, +range)                          saturation
//   out_k = Q (floor(theta_k / Q) - floor(theta_{k-1} / Q)) / dt_k,  theta_k = theta_{k-1} + w_k dt_k
//                                                              angle quantization (IEEE Std 952 D_Q)
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/excitation.h"
#include "core/thermal_lag.h"
#include "sensor/gyro_error_model.h"
#include "sensor/misalignment.h"
#include "noise/processes.h"

namespace gyrosid {

// The sensor package's thermal path: chamber --(delay, tau_s)--> probe --(coil_tau_s)--> coil.
struct ThermalPath {
  double delay_s = 0.0;
  double tau_s = 0.0;       // chamber -> probe (thesis s4.4: about 5 min for the package)
  double coil_tau_s = 0.0;  // probe -> coil (0: the probe reads the coil temperature, the thesis's case)
  ThermalLagOptions lag_options() const { return {delay_s, {tau_s, coil_tau_s}}; }
  std::string validate() const;
};

struct GyroSensor {
  std::string name;
  GyroErrorModel errors;
  NoiseOptions noise;
  double quantization_rad = 0.0;  // angle per output pulse, Q (0: none)
  double range_radps = std::numeric_limits<double>::infinity();
  ThermalPath thermal;

  std::string validate() const;
};

struct TriadSensor {
  std::string name;
  std::array<GyroSensor, 3> gyros;
  std::array<GyroAlignment, 3> alignment;
  ThermalPath thermal;  // one package: the gyros' own thermal paths are not used in a triad

  std::string validate() const;
};

struct GyroOutput {
  std::vector<double> rate_radps;
  std::size_t clamped_samples = 0;    // samples where the error surface was clamped at its grid edge
  std::size_t saturated_samples = 0;  // samples clipped at the measurement range
};

// One gyro whose input axis in body axes is `input_axis_b` and whose sensor axes are C_s_b (body ->
// sensor, rows = sensor axes in body; its third row is the input axis). Noise streams are named
// "<stream>/arw", ... so every gyro of a triad draws independently.
GyroOutput simulate_gyro(const GyroSensor& sensor, const Excitation& excitation, const Eigen::Matrix3d& c_s_b,
                         std::uint64_t seed, const std::string& stream);

// Single gyro with its input axis along body z (sensor axes = body axes).
GyroOutput simulate_single(const GyroSensor& sensor, const Excitation& excitation, std::uint64_t seed);

struct TriadOutput {
  std::array<GyroOutput, 3> gyro;
};
TriadOutput simulate_triad(const TriadSensor& sensor, const Excitation& excitation, std::uint64_t seed);

}  // namespace gyrosid
