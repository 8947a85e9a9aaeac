// Flight trajectories for the criterion of fit (thesis s4.5, appendix C): a segment-based kinematic
// generator of position, velocity, attitude, body rates and specific forces that are consistent to
// integration precision, plus the thesis-shaped built-ins `short`, `medium`, `long`, and CSV import.
//
// Point-mass flight with the body x axis along the velocity (no angle of attack or sideslip): speed V,
// flight-path angle gamma, heading chi, bank phi; attitude = (yaw chi, pitch gamma, roll phi). Segments
// command smooth time profiles of dV/dt, dgamma/dt, the bank (turns are coordinated: dchi/dt = g tan(phi)/V)
// and roll rate; every command starts and ends at zero rate, so body rates are continuous. Then, on WGS-84:
//   v_n   = V (cos g cos chi, cos g sin chi, -sin g)
//   f_b   = C_b_n (dv_n/dt + (2 omega_ie_n + omega_en_n) x v_n - g_n)
//   w_ib_b = w_nb_b(Euler rates) + C_b_n (omega_ie_n + omega_en_n)
// The state and the IMU integrals (delta-theta = integral of w_ib_b, delta-v = integral of f_b, body axes)
// are integrated together by fourth-order Runge-Kutta on `substeps` substeps of each output interval.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/config.h"
#include "core/enum_names.h"
#include "core/nav_state.h"

namespace gyrosid {

enum class FlightSegmentKind { straight, accelerate, climb, dive, level_turn, roll, pull_up, s_turn };

template <>
struct EnumNames<FlightSegmentKind> {
  static constexpr std::string_view kNoun = "flight segment kind";
  static constexpr std::array<std::pair<FlightSegmentKind, std::string_view>, 8> kTable{
      {{FlightSegmentKind::straight, "straight"}, {FlightSegmentKind::accelerate, "accelerate"},
       {FlightSegmentKind::climb, "climb"}, {FlightSegmentKind::dive, "dive"},
       {FlightSegmentKind::level_turn, "level_turn"}, {FlightSegmentKind::roll, "roll"},
       {FlightSegmentKind::pull_up, "pull_up"}, {FlightSegmentKind::s_turn, "s_turn"}}};
};

struct FlightSegment {
  FlightSegmentKind kind = FlightSegmentKind::straight;
  double duration_s = 1.0;
  double accel_mps2 = 0.0;    // accelerate (may be negative)
  double angle_deg = 0.0;     // climb/dive: flight-path angle change; roll: roll angle change
  double bank_deg = 0.0;      // level_turn, s_turn: bank of the coordinated turn
  double load_factor = 1.0;   // pull_up: peak load factor n
  int turns = 2;              // s_turn: half-cycles of bank
  std::string validate() const;
};

struct FlightInitial {
  double lat_deg = -25.86, lon_deg = 28.19, h_m = 769.0;  // 769 m: 10 C in the standard atmosphere
  double speed_mps = 100.0, flight_path_deg = 0.0, heading_deg = 0.0, bank_deg = 0.0;
};

struct FlightProfile {
  std::string name;
  std::string description;
  FlightInitial initial;
  std::vector<FlightSegment> segments;
  int substeps = 10;  // RK4 substeps per output interval (slow flights need fewer)
  double duration_s() const;
  std::string validate() const;
};

// Samples at t_k = k dt, k = 0..K; interval k is (t_k, t_{k+1}].
struct FlightTrajectory {
  std::string name;
  double dt_s = 0.01;
  std::vector<double> t_s;               // K + 1
  std::vector<NavState> truth;           // K + 1 (empty when imported without truth)
  std::vector<Eigen::Vector3d> dtheta;   // K, rad, body axes
  std::vector<Eigen::Vector3d> dv;       // K, m/s, body axes
  NavState initial() const;
  std::size_t steps() const { return dtheta.size(); }
  double duration_s() const { return dt_s * static_cast<double>(steps()); }
};

// substeps <= 0: the profile's own.
FlightTrajectory generate_flight(const FlightProfile& profile, double rate_hz, int substeps = 0);

// The thesis-shaped built-ins (appendix C): short (~10 s air-to-air missile turn-around, up to 48 g and
// fast rolls), medium (~50 s missile: vertical launch, pitch-over, cruise with S-turns, terminal dive),
// long (~2 h UAV: climb to 6 km, racetracks, descent).
FlightProfile builtin_flight(std::string_view name);
std::vector<std::string> builtin_flight_names();
FlightProfile load_flight_profile(const ConfigNode& node);

// CSV import: t_s and the mean body rate and specific force over the interval ending at each row
// (omega_x_dps, omega_y_dps, omega_z_dps, f_x_mps2, f_y_mps2, f_z_mps2; first row's values unused), the
// initial state on the first row (lat_deg, lon_deg, h_m, v_n_mps, v_e_mps, v_d_mps, roll_deg, pitch_deg,
// yaw_deg), optionally on every row (then kept as truth). Uniform sampling required.
FlightTrajectory load_flight_csv(const std::string& path);
FlightTrajectory parse_flight_csv(const std::string& text, const std::string& source);

// Standard-atmosphere temperature along the flight (thesis eq C.1, lapse -0.0065 K/m), shifted so that the
// first sample is at `start_temp_c`.
std::vector<double> flight_temperature_c(const FlightTrajectory& f, double start_temp_c);

}  // namespace gyrosid
