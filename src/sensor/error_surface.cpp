#include "sensor/error_surface.h"

#include "core/earth.h"
#include "core/units.h"

namespace gyrosid {

const GyroSensor& representative_gyro(const SensorSpec& sensor) {
  if (const auto* g = std::get_if<GyroSensor>(&sensor)) return *g;
  return std::get<TriadSensor>(sensor).gyros[2];
}

std::function<double(double, double)> error_surface_dps(const GyroSensor& gyro) {
  return [&gyro](double temp_c, double rate_dps) {
    GyroEnvironment env;
    env.temp_c = temp_c;
    env.f_s = Eigen::Vector3d(0, 0, earth::normal_gravity(0.0));
    const double w = units::dps_to_radps(rate_dps);
    return units::radps_to_dps(gyro.errors.forward(w, env) - w);
  };
}

}  // namespace gyrosid
