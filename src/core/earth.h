// WGS-84 Earth constants (NIMA TR8350.2) used by the calibration tables and the strapdown INS.
#pragma once

namespace gyrosid::earth {

inline constexpr double kRotationRate = 7.292115e-5;         // Omega_ie, rad/s
inline constexpr double kSemiMajorAxis = 6378137.0;          // a, m
inline constexpr double kFlattening = 1.0 / 298.257223563;   // f
inline constexpr double kEccentricitySq = kFlattening * (2.0 - kFlattening);  // e^2
inline constexpr double kGravityEquator = 9.7803253359;      // gamma_e, m/s^2 (Somigliana)
inline constexpr double kGravityPole = 9.8321849378;         // gamma_p, m/s^2
inline constexpr double kGm = 3.986004418e14;                // GM, m^3/s^2

}  // namespace gyrosid::earth

#include <cmath>

namespace gyrosid::earth {

// Normal gravity on the WGS-84 ellipsoid at geodetic latitude `lat` (rad), Somigliana's formula, with the
// free-air height correction of Titterton & Weston eq. 3.91 (gamma (1 - 2h/a)) - adequate to 1e-6 g below
// 20 km. Includes the centrifugal part: it is what a resting accelerometer measures (with a sign flip).
inline double normal_gravity(double lat, double height_m = 0.0) {
  const double s2 = std::sin(lat) * std::sin(lat);
  const double k = (kSemiMajorAxis * std::sqrt(1.0 - kEccentricitySq) * kGravityPole) / (kSemiMajorAxis * kGravityEquator) - 1.0;
  const double gamma0 = kGravityEquator * (1.0 + k * s2) / std::sqrt(1.0 - kEccentricitySq * s2);
  return gamma0 * (1.0 - 2.0 * height_m / kSemiMajorAxis);
}

}  // namespace gyrosid::earth
