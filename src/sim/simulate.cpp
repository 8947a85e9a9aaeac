#include "sim/simulate.h"

#include "core/error.h"

namespace gyrosid {

Simulation simulate(const SensorSpec& sensor, const TrajectorySpec& trajectory, std::uint64_t seed) {
  Simulation s{sensor, trajectory, {}, {}, {}};
  s.excitation = excite(trajectory.profile, trajectory.times(), thermal_path(sensor).lag_options());
  s.recording = simulate_recording(sensor, s.excitation, seed, &s.summary);
  std::string description = trajectory.profile.kind + " '" + trajectory.profile.name + "'";
  if (!trajectory.description.empty()) description += ": " + trajectory.description;
  s.recording.set_meta("description", description);
  return s;
}

SensorSpec without_noise(SensorSpec sensor) {
  auto strip = [](GyroSensor& g) {
    g.noise = NoiseOptions{};
    g.quantization_rad = 0.0;
  };
  if (auto* g = std::get_if<GyroSensor>(&sensor)) strip(*g);
  else
    for (auto& g : std::get<TriadSensor>(sensor).gyros) strip(g);
  return sensor;
}

Simulation simulate_files(const std::string& sensor_path, const std::string& trajectory_path, std::uint64_t seed,
                          std::optional<std::size_t> samples_override, bool noise_free) {
  SensorSpec sensor = load_sensor_file(sensor_path);
  if (noise_free) sensor = without_noise(std::move(sensor));
  TrajectorySpec trajectory = load_trajectory_file(trajectory_path);
  if (samples_override) {
    if (*samples_override < 2) fail("--samples ", *samples_override, ": need at least 2");
    trajectory.sampling = Sampling{*samples_override, 0.0};
  }
  return simulate(sensor, trajectory, seed);
}

std::string describe(const Simulation& s) {
  return str_cat(s.recording.rows(), " samples over ", s.trajectory.profile.duration_min(), " min (",
                 s.trajectory.profile.kind, " '", s.trajectory.profile.name, "'), ",
                 std::holds_alternative<TriadSensor>(s.sensor) ? "triad" : "single gyro", " '", sensor_name(s.sensor),
                 "'", s.summary.clamped_samples ? str_cat(", ", s.summary.clamped_samples, " samples beyond the error-surface grid (clamped)") : "",
                 s.summary.saturated_samples ? str_cat(", ", s.summary.saturated_samples, " saturated") : "");
}

}  // namespace gyrosid
