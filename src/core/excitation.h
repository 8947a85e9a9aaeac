// What a rate table and a thermal chamber apply to a sensor over time - the input of a simulation, produced
// by a calibration trajectory (src/trajectory) and consumed by the sensor simulator (src/sensor).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace gyrosid {

struct Excitation {
  std::vector<double> t_s;
  std::vector<Eigen::Vector3d> omega_ib_b;  // body rate w.r.t. inertial space, body axes, rad/s (Earth rate included)
  std::vector<Eigen::Vector3d> f_b;         // specific force, body axes, m/s^2
  std::vector<double> chamber_temp_c;       // chamber air
  std::vector<double> probe_temp_c;         // the temperature probe in the sensor package
  std::vector<double> coil_temp_c;          // the sensing coil (what the error model depends on)
  std::vector<double> coil_temp_rate_c_per_s;
  std::vector<int> position_id;             // table position label per sample (empty when not defined)
  double latitude_rad = 0.0;

  std::size_t size() const { return t_s.size(); }
};

}  // namespace gyrosid
