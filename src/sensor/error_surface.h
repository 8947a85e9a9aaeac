// The "true error surface" of a gyro (thesis fig 3.12): its deterministic rate error at steady temperature
// on a level table, input axis up (specific force 1 g along it), as a function of (T, omega).
#pragma once

#include <functional>

#include "sensor/sensor_config.h"

namespace gyrosid {

// Rate error in deg/s at (temperature deg C, true rate deg/s).
std::function<double(double temp_c, double rate_dps)> error_surface_dps(const GyroSensor& gyro);
// The gyro a single-axis study looks at: the single gyro, or a triad's z gyro.
const GyroSensor& representative_gyro(const SensorSpec& sensor);

}  // namespace gyrosid
