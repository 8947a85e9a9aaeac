// A navigation state: geodetic position, NED velocity, body attitude. The truth of a flight trajectory
// (src/trajectory) and the solution of the strapdown INS (src/nav) share it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gyrosid {

struct NavState {
  double lat = 0.0, lon = 0.0, h = 0.0;           // rad, rad, m (WGS-84 geodetic)
  Eigen::Vector3d v_n = Eigen::Vector3d::Zero();  // m/s, north-east-down
  Eigen::Quaterniond q_n_b = Eigen::Quaterniond::Identity();  // body -> NED
};

// C_n_b from 3-2-1 Euler angles (yaw psi about D, pitch theta, roll phi), all rad.
inline Eigen::Quaterniond euler_to_quaternion(double roll, double pitch, double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

}  // namespace gyrosid
