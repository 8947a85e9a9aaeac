// Elementary rotation matrices (active, right-handed): R_x(a) v rotates v by angle a about x.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace gyrosid {

inline Eigen::Matrix3d rotation_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

inline Eigen::Matrix3d rotation_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}

inline Eigen::Matrix3d rotation_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

}  // namespace gyrosid
