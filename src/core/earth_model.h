// WGS-84 Earth for navigation in local geographic (NED) axes (Titterton & Weston ch. 3):
//   R_N = a(1 - e^2) / (1 - e^2 sin^2 L)^{3/2}   meridian radius
//   R_E = a / (1 - e^2 sin^2 L)^{1/2}            transverse radius
//   omega_ie_n = Omega (cos L, 0, -sin L)
//   omega_en_n = (v_E/(R_E + h), -v_N/(R_N + h), -v_E tan L/(R_E + h))
//   g_n = (0, 0, gamma(L, h))                  normal gravity (plumb line along D)
#pragma once

#include <Eigen/Core>

#include <cmath>

#include "core/earth.h"

namespace gyrosid::earth {


struct EarthRadii {
  double meridian;    // R_N
  double transverse;  // R_E
};

inline EarthRadii radii(double lat) {
  const double s = std::sin(lat);
  const double k = 1.0 - kEccentricitySq * s * s;
  const double sq = std::sqrt(k);
  return {kSemiMajorAxis * (1.0 - kEccentricitySq) / (k * sq), kSemiMajorAxis / sq};
}

inline Eigen::Vector3d earth_rate_n(double lat) {
  return {kRotationRate * std::cos(lat), 0.0, -kRotationRate * std::sin(lat)};
}

inline Eigen::Vector3d transport_rate_n(double lat, double h, const Eigen::Vector3d& v_n, const EarthRadii& r) {
  return {v_n.y() / (r.transverse + h), -v_n.x() / (r.meridian + h), -v_n.y() * std::tan(lat) / (r.transverse + h)};
}

inline Eigen::Vector3d gravity_n(double lat, double h) { return {0.0, 0.0, normal_gravity(lat, h)}; }

// NED displacement (m) of point b from point a, both geodetic (rad, rad, m); small-distance form with the
// radii at a (exact to well below a millimetre for the kilometres of a criterion-of-fit end error).
inline Eigen::Vector3d ned_offset(double lat_a, double lon_a, double h_a, double lat_b, double lon_b, double h_b) {
  const EarthRadii r = radii(0.5 * (lat_a + lat_b));
  return {(lat_b - lat_a) * (r.meridian + 0.5 * (h_a + h_b)),
          (lon_b - lon_a) * (r.transverse + 0.5 * (h_a + h_b)) * std::cos(0.5 * (lat_a + lat_b)), -(h_b - h_a)};
}

}  // namespace gyrosid::earth
