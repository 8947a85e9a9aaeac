#include "sensor/misalignment.h"

#include <cmath>

#include "core/error.h"

namespace gyrosid {

Eigen::Matrix3d ra_from_ia(double angle_x, double angle_y) { return rotation_x(angle_x) * rotation_y(angle_y); }

Eigen::Matrix3d ca_from_ra(int axis) {
  // Columns: the RA x, y, z axes expressed in CA. RA z goes to CA `axis`; cyclic, so det = +1.
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();
  switch (axis) {
    case 0: p(1, 0) = 1; p(2, 1) = 1; p(0, 2) = 1; break;  // x gyro: RA x->CA y, y->z, z->x
    case 1: p(2, 0) = 1; p(0, 1) = 1; p(1, 2) = 1; break;  // y gyro: RA x->CA z, y->x, z->y
    case 2: p.setIdentity(); break;
    default: fail("ca_from_ra: axis ", axis, " is not 0, 1 or 2");
  }
  return p;
}

Eigen::Matrix3d body_from_ca(int axis, double angle_x, double angle_y) {
  // The insertion rotation has the same form as the IA->RA one, about the gyro's own perpendicular axes.
  const Eigen::Matrix3d p = ca_from_ra(axis);
  return p * ra_from_ia(angle_x, angle_y) * p.transpose();
}

Eigen::Matrix3d body_from_ia(int axis, const GyroAlignment& a) {
  return body_from_ca(axis, a.insertion_x, a.insertion_y) * ca_from_ra(axis) * ra_from_ia(a.ia_x, a.ia_y);
}

Eigen::Matrix3d measurement_matrix(const std::array<GyroAlignment, 3>& alignment) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) m.row(i) = (body_from_ia(i, alignment[i]) * Eigen::Vector3d::UnitZ()).transpose();
  return m;
}

Eigen::Matrix3d measurement_matrix_small_angle(const std::array<GyroAlignment, 3>& g) {
  const double ax = g[0].ia_x + g[0].insertion_x, ay = g[0].ia_y + g[0].insertion_y;  // phi + mu
  const double bx = g[1].ia_x + g[1].insertion_x, by = g[1].ia_y + g[1].insertion_y;  // theta + eta
  const double cx = g[2].ia_x + g[2].insertion_x, cy = g[2].ia_y + g[2].insertion_y;  // psi + xi
  Eigen::Matrix3d m;
  m << 1, ay, -ax,
       -bx, 1, by,
       cy, -cx, 1;
  return m;
}

}  // namespace gyrosid
