// Calibration trajectories: what a single-axis rate table inside a thermal chamber does over time
// (thesis s4.4 and Table 2.1). A profile is a sequence of segments; in each the chamber temperature moves
// linearly from start to end and the table turns at a constant or triangle-wave rate about its vertical
// axis, with the sensor mounted in one of the six positions of Table 2.1.
//
// Geometry: the table frame coincides with local NED when the table angle is zero; the table turns about
// Up at rate Omega_r (positive counter-clockwise seen from above), so body rate and specific force are
//   omega_ib_b = C_b_n omega_ie_n + C_b_t (0, 0, -Omega_r),   f_b = C_b_n (0, 0, -gamma(L)),
// with omega_ie_n = Omega_ie (cos L, 0, -sin L), C_n_b = R_D(-alpha) C_t_b and alpha = integral of Omega_r.
// (Table 2.1 turns the table about Down; turning about Up flips the sign of Omega_r only.)
//
// Mount positions (body axes in table axes at alpha = 0), Table 2.1:
//   1: x=N y=E z=D     2: x=N y=W z=U     3: x=N y=D z=W
//   4: x=N y=U z=E     5: x=D y=E z=S     6: x=U y=E z=N
// A single gyro's input axis is body z, so position 2 (z up) makes the table rate the input rate.
// Beyond Table 2.1, for triads (multi-axis turns, which couple the misalignment to the other gyros' rates):
//   7..10: a body diagonal up, (1,1,1), (-1,-1,1), (-1,1,-1), (1,-1,-1) / sqrt 3 - the table rate reaches
//   every gyro at 1/sqrt 3 of itself, with the signs of that diagonal.
inline constexpr int kMountPositions = 10;
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "core/excitation.h"
#include "core/thermal_lag.h"

namespace gyrosid {

struct RateProfile {
  enum class Shape { constant, triangle } shape = Shape::constant;
  double value_radps = 0.0;  // constant
  double low_radps = 0.0;    // triangle: low -> high -> low per cycle
  double high_radps = 0.0;
  double cycles = 0.0;       // full cycles over the segment
  double phase = 0.0;        // cycle fraction at the segment start, [0, 1)

  double at(double tau, double duration) const;        // rate at time tau into the segment
  double integral(double tau, double duration) const;  // integral of the rate from 0 to tau
  static RateProfile constant(double radps);
  static RateProfile triangle(double low, double high, double cycles, double phase);
  bool operator==(const RateProfile&) const = default;
};

struct ProfileSegment {
  std::string label;
  double duration_s = 0.0;
  double chamber_start_c = 25.0;
  double chamber_end_c = 25.0;
  RateProfile rate;
  int position = 2;  // mount position: Table 2.1's 1..6, body diagonals 7..10 (below)
  bool operator==(const ProfileSegment&) const = default;
};

// What the equipment can do (an equipment file, design/equipment.h, or a programme's `chamber:`/`table:`).
struct ChamberLimits {
  double rate_limit_c_per_min = 5.0;     // heating; thesis s4.4: 5 C/min is "quite a high" chamber rate
  double cooling_limit_c_per_min = NAN;  // NaN: the heating limit (a chamber often cools slower than it heats)
  double min_c = -70.0;
  double max_c = 180.0;
  double limit_c_per_min(bool heating) const {
    return heating || std::isnan(cooling_limit_c_per_min) ? rate_limit_c_per_min : cooling_limit_c_per_min;
  }
  // Where the chamber gets from `from_c` towards `target_c` in `duration_s`, no faster than its limit.
  double reach_c(double from_c, double target_c, double duration_s) const {
    const double heat = rate_limit_c_per_min * duration_s / 60.0, cool = limit_c_per_min(false) * duration_s / 60.0;
    return from_c + std::clamp(target_c - from_c, -cool, heat);
  }
};

struct TableLimits {
  double max_acceleration_radps2 = INFINITY;  // angular acceleration: a triangle's slope 2 (high - low) / period
};

struct TableProfile {
  std::string name;
  std::string kind;
  std::vector<ProfileSegment> segments;
  double latitude_rad = 0.0;
  ChamberLimits limits;
  TableLimits table_limits;

  double duration_s() const;
  double duration_min() const { return duration_s() / 60.0; }
  PiecewiseLinear chamber_temperature() const;  // knots at segment boundaries
  // Empty when every segment respects the chamber limits (range, rate, continuity from segment to segment);
  // otherwise names the first offending segment.
  std::string check_limits() const;
};

// `first` then `then` as one programme (an adaptive session's segments, run one after the other): the
// segments of both, the name, limits and latitude of `first`. Error when `then` does not start where `first`
// ends (the chamber cannot jump) or the latitudes differ.
TableProfile concatenate(const TableProfile& first, const TableProfile& then);

// Body axes in table axes for mount position 1..kMountPositions (columns: body x, y, z).
Eigen::Matrix3d mount_orientation(int position);

// Sample times t_k = k dt over [0, duration): `samples` points (dt = duration / samples) or every
// 1/rate_hz seconds.
struct Sampling {
  std::size_t samples = 0;  // samples over the duration
  double rate_hz = 0.0;
  std::string validate() const;
};
std::vector<double> sample_times(double duration_s, const Sampling& sampling);

// Table rate, attitude, body rate, specific force and chamber temperature at `times`, plus probe and coil
// temperature through `thermal` (stage 0 = probe, last stage = coil; exact for the piecewise-linear
// chamber profile).
Excitation excite(const TableProfile& profile, const std::vector<double>& times, const ThermalLagOptions& thermal);

}  // namespace gyrosid
