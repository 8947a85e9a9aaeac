// Criterion of fit (thesis s4.5, fig 5.3): the reference IMU data of a flight and the same data with all
// three gyros perturbed by the sensor model and then compensated by the model under test go through the
// same strapdown INS; the end-of-trajectory position difference is the criterion. Accelerometers are
// error-free (thesis s4.5: only the gyros under test may move the solution).
//
// Gyro rates are clipped (or scaled) to the calibrated range, as the thesis did (+-100 deg/s); the reference
// INS uses the same clipped data, so the criterion isolates the compensation error. Temperature follows the
// altitude by the standard-atmosphere lapse rate from a start temperature (thesis eq C.1); the coil may lag
// the air by a pure thermal delay (thesis Tables 5.9-5.11); the model is given the coil temperature (the
// gyro's probe, as in the thesis) or, as an option, the air temperature.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "model/calibration_model.h"
#include "model/triad_model.h"
#include "nav/strapdown.h"
#include "sensor/gyro_sensor.h"
#include "trajectory/flight.h"

namespace gyrosid::nav {

enum class CompensationMode { model, none, truth };

// Where the temperature given to the compensation is measured: at the coil (the gyro's own probe, the
// thesis's assumption - a thermal delay then only changes the temperatures the gyro sees) or in the air
// (an external probe - the compensation is then wrong by the delay).
enum class TemperatureProbe { coil, air };
}  // namespace gyrosid::nav

namespace gyrosid {
template <>
struct EnumNames<nav::TemperatureProbe> {
  static constexpr std::string_view kNoun = "temperature probe";
  static constexpr std::array<std::pair<nav::TemperatureProbe, std::string_view>, 2> kTable{
      {{nav::TemperatureProbe::coil, "coil"}, {nav::TemperatureProbe::air, "air"}}};
};
}  // namespace gyrosid

namespace gyrosid::nav {

struct CofOptions {
  double start_temp_c = 10.0;
  double thermal_delay_s = 0.0;
  TemperatureProbe probe = TemperatureProbe::coil;
  double clip_rate_dps = 100.0;  // <= 0: rates used as they are
  bool scale_rates = false;      // scale every rate by the same factor into the range instead of clipping
  std::string validate() const;
};

struct CofRun {
  Eigen::Vector3d error_ned = Eigen::Vector3d::Zero();  // end position minus the reference INS's, m
  double end_error_m = 0.0;
  double error_after_1h_m = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::array<double, 2>> growth;  // (t_s, |error| m), decimated, when recorded
  // The gyro rates fed to the INS minus the reference rates, per body axis (rad/s): what the compensation
  // left, the link between surface statistics and the criterion.
  Eigen::Vector3d residual_mean = Eigen::Vector3d::Zero(), residual_rms = Eigen::Vector3d::Zero();
};

class CofEvaluator {
 public:
  // `model` (any kind, sensor_model.h; null: none): a single gyro's model compensates each gyro on its own, a
  // triad model the three together (misalignment, biases, surfaces).
  CofEvaluator(const FlightTrajectory& flight, const TriadSensor& sensor, const SensorModel* model, const CofOptions& options);

  // One INS run; noise on or off (off: the sensor's deterministic errors only). Deterministic per seed.
  CofRun run(CompensationMode mode, bool noise, std::uint64_t seed, bool record_growth = false) const;
  // Reference runs of the thesis (s5.5): white noise of the given 1-Hz sigma on the reference rates, or a
  // constant bias, with no other error and no compensation.
  CofRun run_reference(double white_sigma_1hz_radps, double bias_radps, std::uint64_t seed) const;

  // (along-track, horizontal cross-track, vertical cross-track) w.r.t. the reference end velocity.
  Eigen::Vector3d decompose(const Eigen::Vector3d& error_ned) const;
  double duration_s() const { return flight_.duration_s(); }
  const std::vector<NavState>& reference_path() const { return reference_path_; }
  const std::vector<double>& air_temperature_c() const { return air_temp_; }
  double max_abs_rate_dps() const { return max_rate_dps_; }
  std::size_t clipped_samples() const { return clipped_; }

  // For the linearised criterion (src/design): the reference rates (clipped) and temperatures, the noise-free
  // sensor outputs per axis, the temperature the model is given, and the position error (NED, m) `at_s`
  // into the flight of the INS fed `rates` (per axis, one per step) instead of the reference rates.
  const Excitation& excitation() const { return excitation_; }
  const std::array<std::vector<double>, 3>& deterministic_outputs() const { return deterministic_; }
  const std::vector<double>& model_temperature_c() const { return probe_temp_; }
  Eigen::Vector3d position_error(const std::array<std::vector<double>, 3>& rates, double at_s) const;
  // Its gradient by the rates about `rates`: position_error changes by sum_k gradient[a].col(k) d rates[a][k]
  // (m per rad/s of gyro axis a at step k), by the adjoint of the INS (strapdown_adjoint.h).
  std::array<Eigen::Matrix3Xd, 3> position_error_gradient(const std::array<std::vector<double>, 3>& rates, double at_s) const;

 private:
  std::size_t steps_to(double at_s) const;
  // INS over the first `steps` steps (all when 0); with `path`, the INS before each step and after the last.
  CofRun integrate(const std::array<std::vector<double>, 3>& rates, bool record_growth, std::size_t steps = 0,
                   std::vector<StrapdownIns>* path = nullptr) const;
  std::array<std::vector<double>, 3> compensate(const std::array<std::vector<double>, 3>& measured) const;

  const FlightTrajectory& flight_;
  TriadSensor sensor_;
  const CalibrationModel* model_;
  const TriadModel* triad_ = nullptr;
  CofOptions options_;
  Excitation excitation_;                        // clipped reference rates, specific force, temperatures
  std::vector<double> air_temp_;                 // from the altitude by the lapse rate
  std::vector<double> probe_temp_, probe_rate_;  // what the model is told
  std::vector<NavState> reference_path_;         // reference INS, every step
  std::array<std::vector<double>, 3> deterministic_;  // noise-free sensor outputs
  std::array<Eigen::Matrix3d, 3> c_s_b_;
  double max_rate_dps_ = 0.0;
  std::size_t clipped_ = 0;
};

}  // namespace gyrosid::nav
