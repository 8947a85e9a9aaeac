#include "sensor/simulate_recording.h"

#include <cmath>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {
namespace {

std::vector<double> to_dps(const std::vector<double>& radps) {
  std::vector<double> out(radps.size());
  for (std::size_t i = 0; i < radps.size(); ++i) out[i] = units::radps_to_dps(radps[i]);
  return out;
}

std::vector<double> component(const std::vector<Eigen::Vector3d>& v, int axis, double scale) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i](axis) * scale;
  return out;
}

void add_common_metadata(Recording& rec, const SensorSpec& sensor, const Excitation& ex, std::uint64_t seed) {
  rec.set_meta("sensor", sensor_name(sensor) + ", simulated");
  if (ex.size() > 1) {
    const double dt = (ex.t_s.back() - ex.t_s.front()) / static_cast<double>(ex.size() - 1);
    rec.set_meta("sample_rate_hz", format_number(1.0 / dt));
  }
  rec.set_meta("latitude_deg", format_number(units::rad_to_deg(ex.latitude_rad)));
  rec.set_meta("seed", std::to_string(seed));
}

}  // namespace

Recording simulate_recording(const SensorSpec& sensor, const Excitation& ex, std::uint64_t seed,
                             SimulationSummary* summary) {
  Recording rec("<simulation>");
  add_common_metadata(rec, sensor, ex, seed);
  SimulationSummary s;
  s.samples = ex.size();
  rec.set_column("t_s", ex.t_s);
  if (const auto* gyro = std::get_if<GyroSensor>(&sensor)) {
    const GyroOutput out = simulate_single(*gyro, ex, seed);
    rec.set_column("ref_rate_dps", to_dps(component(ex.omega_ib_b, 2, 1.0)));
    rec.set_column("temp_c", ex.probe_temp_c);
    rec.set_column("gyro_dps", to_dps(out.rate_radps));
    s.clamped_samples = out.clamped_samples;
    s.saturated_samples = out.saturated_samples;
  } else {
    const auto& triad = std::get<TriadSensor>(sensor);
    const TriadOutput out = simulate_triad(triad, ex, seed);
    for (int i = 0; i < 3; ++i) {
      rec.set_column(std::string("ref_rate_") + kTriadAxes[i] + "_dps", to_dps(component(ex.omega_ib_b, i, 1.0)));
    }
    for (int i = 0; i < 3; ++i) {
      rec.set_column(std::string("gyro_") + kTriadAxes[i] + "_dps", to_dps(out.gyro[i].rate_radps));
      s.clamped_samples += out.gyro[i].clamped_samples;
      s.saturated_samples += out.gyro[i].saturated_samples;
    }
    rec.set_column("temp_c", ex.probe_temp_c);
  }
  rec.set_column("chamber_temp_c", ex.chamber_temp_c);
  for (int i = 0; i < 3; ++i) rec.set_column(std::string("accel_") + "xyz"[i] + "_mps2", component(ex.f_b, i, 1.0));
  if (std::holds_alternative<TriadSensor>(sensor) && !ex.position_id.empty()) {
    rec.set_column("position_id", std::vector<double>(ex.position_id.begin(), ex.position_id.end()));
  }
  if (summary) *summary = s;
  return rec;
}

}  // namespace gyrosid
