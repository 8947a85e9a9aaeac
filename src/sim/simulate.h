// The simulation driver: a sensor (src/sensor) driven along a calibration trajectory (src/trajectory),
// with the chamber-to-coil thermal path of the sensor's package, producing a recording. It sits above both
// layers so that neither depends on the other.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/recording.h"
#include "sensor/sensor_config.h"
#include "sensor/simulate_recording.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {

struct Simulation {
  SensorSpec sensor;
  TrajectorySpec trajectory;
  Excitation excitation;
  Recording recording;
  SimulationSummary summary;
};

Simulation simulate(const SensorSpec& sensor, const TrajectorySpec& trajectory, std::uint64_t seed);

// The sensor without its random drift and quantization: deterministic errors only (noise-free studies).
SensorSpec without_noise(SensorSpec sensor);
// `gyrosid simulate`: the files' sensor (without its noise when asked) along their trajectory, with another
// number of samples over the same duration when given.
Simulation simulate_files(const std::string& sensor_path, const std::string& trajectory_path, std::uint64_t seed,
                          std::optional<std::size_t> samples_override = std::nullopt, bool noise_free = false);

// One line for humans: "11110 samples over 62 min (dual_scan 'dual scan'), sensor 'open-loop FOG'".
std::string describe(const Simulation& simulation);

}  // namespace gyrosid
