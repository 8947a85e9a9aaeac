// The strapdown INS: an error-free IMU stream from a generated flight reproduces the flight; a resting IMU
// fed exact Earth rate and gravity stays put; a 1 deg/h gyro bias gives the textbook Schuler error.
#include <gtest/gtest.h>

#include <cmath>

#include "core/earth_model.h"
#include "core/units.h"
#include "nav/strapdown.h"
#include "trajectory/flight.h"

namespace gyrosid::nav {
namespace {

double end_position_error(const FlightTrajectory& f) {
  StrapdownIns ins(f.initial(), f.dt_s);
  for (std::size_t k = 0; k < f.steps(); ++k) ins.step(f.dtheta[k], f.dv[k]);
  const NavState& a = f.truth.back();
  const NavState& b = ins.state();
  return earth::ned_offset(a.lat, a.lon, a.h, b.lat, b.lon, b.h).norm();
}

// What remains is the INS's own algorithm error: two-sample coning and sculling and mid-interval
// evaluation of the navigation-frame terms, O(dt^2) per step against the generator's RK4 integrals.
TEST(Strapdown, ErrorFreeImuReproducesTheShortFlightToAMillimetre) {
  const FlightTrajectory f = generate_flight(builtin_flight("short"), 100.0);
  EXPECT_NEAR(f.duration_s(), 10.0, 1e-9);
  EXPECT_LT(end_position_error(f), 1e-3);
}

TEST(Strapdown, ErrorFreeImuReproducesTheMediumFlight) {
  const FlightTrajectory f = generate_flight(builtin_flight("medium"), 100.0);
  EXPECT_LT(end_position_error(f), 1e-2);
}

TEST(Strapdown, ErrorFreeImuReproducesTheTwoHourFlightToAMetre) {
  FlightProfile p = builtin_flight("long");
  const FlightTrajectory f = generate_flight(p, 100.0);
  EXPECT_GT(f.duration_s(), 7000.0);
  EXPECT_LT(end_position_error(f), 1.0);
}

TEST(Strapdown, RestingImuWithExactEarthRateAndGravityDoesNotDrift) {
  NavState s;
  s.lat = units::deg_to_rad(-25.86), s.lon = units::deg_to_rad(28.19), s.h = 1500.0;
  const double dt = 0.01;
  const Eigen::Vector3d dtheta = earth::earth_rate_n(s.lat) * dt;  // body = NED, turning with the Earth
  const Eigen::Vector3d dv = -earth::gravity_n(s.lat, s.h) * dt;   // specific force at rest
  StrapdownIns ins(s, dt);
  for (int k = 0; k < 360000; ++k) ins.step(dtheta, dv);  // one hour
  const NavState& e = ins.state();
  EXPECT_LT(earth::ned_offset(s.lat, s.lon, s.h, e.lat, e.lon, e.h).norm(), 1e-3);
  EXPECT_LT(e.v_n.norm(), 1e-6);
  EXPECT_LT(e.q_n_b.angularDistance(s.q_n_b), 1e-10);
}

TEST(Strapdown, GyroBiasGivesTheSchulerModulatedPositionError) {
  // At the equator, body = NED at rest, an east-gyro bias eps: the north channel obeys the Schuler loop
  //   dv_N(t) = -R eps (1 - cos(w_s t)),  dN(t) = -R eps (t - sin(w_s t) / w_s),  w_s = sqrt(g / R_N),
  // period 2 pi / w_s = 84.28 min with the meridian radius at the equator (Titterton & Weston s12.3).
  // Over half a Schuler period the neglected couplings stay below 1 %: Earth rate turns the tilt into
  // azimuth (relative ~ (Omega t)^2 / 2) and the free vertical channel (time constant sqrt(R / 2 g) ~ 9 min)
  // has only grown to metres; beyond an hour they dominate, so the comparison stops there.
  NavState s;
  const double dt = 0.05, eps = units::dph_to_radps(1.0);
  const double g = earth::normal_gravity(0.0), r = earth::radii(0.0).meridian;
  const double ws = std::sqrt(g / r);
  EXPECT_NEAR(2.0 * units::kPi / ws / 60.0, 84.28, 0.01);
  const Eigen::Vector3d dtheta = (earth::earth_rate_n(0.0) + Eigen::Vector3d(0.0, eps, 0.0)) * dt;
  const Eigen::Vector3d dv = -earth::gravity_n(0.0, 0.0) * dt;
  StrapdownIns ins(s, dt);
  double worst = 0.0, peak_v = 0.0, peak_t = 0.0;
  for (int k = 1; k <= static_cast<int>(2700.0 / dt); ++k) {
    ins.step(dtheta, dv);
    const double t = k * dt;
    const double north = (ins.state().lat - s.lat) * r;
    const double expected = -r * eps * (t - std::sin(ws * t) / ws);
    if (t >= 300.0) worst = std::max(worst, std::abs(north - expected) / std::abs(expected));
    const double v = -ins.state().v_n.x();
    if (v > peak_v) peak_v = v, peak_t = t;
  }
  EXPECT_LT(worst, 0.01);
  // The velocity error peaks at 2 R eps half a Schuler period in.
  EXPECT_NEAR(peak_t / 60.0, units::kPi / ws / 60.0, 1.0);
  EXPECT_NEAR(peak_v / (2.0 * r * eps), 1.0, 0.02);
}

}  // namespace
}  // namespace gyrosid::nav
