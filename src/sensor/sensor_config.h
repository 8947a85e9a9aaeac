// Sensor configurations in YAML (configs/sensors/*.yaml). Units are in the key names; everything is
// converted to SI on load. A file describes either one gyro (kind: gyro) or a triad (kind: triad); see
// configs/sensors/open_loop_fog.yaml and fog_triad.yaml for every key with its meaning.
#pragma once

#include <string>
#include <variant>

#include "core/config.h"
#include "sensor/gyro_sensor.h"

namespace gyrosid {

using SensorSpec = std::variant<GyroSensor, TriadSensor>;

GyroSensor load_gyro(const ConfigNode& node);
TriadSensor load_triad(const ConfigNode& node);
SensorSpec load_sensor(const ConfigNode& node);
SensorSpec load_sensor_file(const std::string& path);

const ThermalPath& thermal_path(const SensorSpec& spec);
// A triad: the spec itself, or three copies of a single gyro on perfectly aligned axes.
TriadSensor as_triad(const SensorSpec& spec);
const std::string& sensor_name(const SensorSpec& spec);
// The spec with every gyro's noise replaced (an identified noise model in place of the config's).
SensorSpec with_gyro_noise(SensorSpec spec, const NoiseOptions& noise);

}  // namespace gyrosid
