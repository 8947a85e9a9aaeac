// Calibration trajectories: durations equal the hand calculation, chamber limits hold, rates stay in range,
// the dual scan's rate cycles are out of phase, Table 2.1's Earth-rate components, exact table angle.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <set>

#include "core/earth.h"
#include "core/error.h"
#include "core/units.h"
#include "trajectory/calibration_trajectories.h"
#include "trajectory/programme.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

using namespace units;

ScanOptions thesis_scan() {
  ScanOptions o;
  o.temp_low_c = -60;
  o.temp_high_c = 80;
  o.scan_rate_c_per_min = 5;
  o.rate_low_radps = dps_to_radps(-100);
  o.rate_high_radps = dps_to_radps(100);
  o.rate_cycles_per_scan = 16;
  o.boundary_scan_min = 0;
  return o;
}

TEST(Trajectories, DurationsEqualTheHandCalculation) {
  ScanOptions o = thesis_scan();
  EXPECT_DOUBLE_EQ(single_scan(o).duration_min(), 28.0);  // 140 C / 5 C/min
  EXPECT_DOUBLE_EQ(dual_scan(o).duration_min(), 56.0);
  o.temperature_cycles = 4;
  o.rate_cycles_per_scan = 8;
  EXPECT_DOUBLE_EQ(test_cycles(o).duration_min(), 224.0);  // 4 x 56
  o.boundary_scan_min = 2;
  EXPECT_DOUBLE_EQ(single_scan(o).duration_min(), 32.0);
  EXPECT_DOUBLE_EQ(dual_scan(o).duration_min(), 62.0);
  // Classical soak: 7 ramps of 20 C at 5 C/min + 8 x (30 min settle + 6 positions x 13 rates x 20 s).
  const auto soak = load_trajectory_file("builtin:trajectories/classical_soak.yaml");
  EXPECT_NEAR(soak.profile.duration_min(), 7 * 4.0 + 8 * (30.0 + 6 * 13 * 20 / 60.0), 1e-9);
  EXPECT_NEAR(soak.profile.duration_min() / 60.0, 7.93, 0.01);  // "about 8 h"
  RampOptions r;
  r.temp_start_c = 20;
  r.temp_end_c = -40;
  r.rate_c_per_min = 2;
  r.hold_start_min = 5;
  r.hold_end_min = 10;
  EXPECT_DOUBLE_EQ(thermal_ramp(r).duration_min(), 45.0);
}

TEST(Trajectories, ShippedConfigsHaveTheThesisNumbers) {
  const auto dual = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  EXPECT_EQ(dual.times().size(), 11110u);
  EXPECT_DOUBLE_EQ(dual.profile.duration_min(), 62.0);  // 56 min of ramps + 3 boundary scans
  const auto test = load_trajectory_file("builtin:trajectories/test_4x16.yaml");
  EXPECT_DOUBLE_EQ(test.profile.duration_min(), 224.0);
  EXPECT_EQ(test.times().size(), 224u * 60);
  const auto single = load_trajectory_file("builtin:trajectories/single_scan.yaml");
  EXPECT_DOUBLE_EQ(single.profile.duration_min(), 32.0);
}

TEST(Trajectories, ChamberLimitsAndRateRangeAreRespected) {
  for (const char* name : {"dual_scan", "single_scan", "test_4x16", "classical_soak"}) {
    const auto spec = load_trajectory_file(std::string("builtin:trajectories/") + name + ".yaml");
    std::vector<double> t;
    for (double s = 0; s <= spec.profile.duration_s(); s += 1.0) t.push_back(s);
    const Excitation ex = excite(spec.profile, t, {0.0, {300.0}});
    double max_rate = 0, max_table = 0;
    for (std::size_t k = 1; k < t.size(); ++k) {
      max_rate = std::max(max_rate, std::abs(ex.chamber_temp_c[k] - ex.chamber_temp_c[k - 1]) / (t[k] - t[k - 1]) * 60);
    }
    for (std::size_t k = 0; k < t.size(); ++k) {
      EXPECT_GE(ex.chamber_temp_c[k], -60.0 - 1e-9);
      EXPECT_LE(ex.chamber_temp_c[k], 80.0 + 1e-9);
      max_table = std::max(max_table, ex.omega_ib_b[k].norm());
    }
    EXPECT_LE(max_rate, 5.0 + 1e-9) << name;
    EXPECT_LE(radps_to_dps(max_table), 100.0 + 0.01) << name;  // table rate plus Earth rate
  }
}

TEST(Trajectories, LimitViolationsAreErrorsNamingTheSegment) {
  ScanOptions o = thesis_scan();
  o.scan_rate_c_per_min = 8;
  TableProfile p = dual_scan(o);
  EXPECT_THAT(p.check_limits(), ::testing::HasSubstr("segment 1 ('up scan'"));
  EXPECT_THAT(p.check_limits(), ::testing::HasSubstr("exceeds the chamber's limit 5"));
  p.limits.rate_limit_c_per_min = 10;
  p.limits.min_c = -40;
  EXPECT_THAT(p.check_limits(), ::testing::HasSubstr("outside the chamber range"));
  const ConfigNode bad = ConfigNode::parse(
      "kind: dual_scan\ntemperature_c: [-60, 80]\nscan_rate_c_per_min: 6\nrate_dps: [-100, 100]\n"
      "rate_cycles_per_scan: 16\nsampling: {samples: 100}\n",
      "bad.yaml");
  try {
    load_trajectory(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("bad.yaml:1"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("6 C/min exceeds the chamber's limit 5"));
  }
}

TEST(Trajectories, DualScanRateCyclesAreOutOfPhaseAtEachTemperature) {
  // With whole cycles per scan and the down scan started half a cycle on, the rate at a chamber
  // temperature on the way down mirrors the rate at that temperature on the way up: w_down = lo + hi - w_up.
  const TableProfile p = dual_scan(thesis_scan());
  const double up = p.segments[0].duration_s;
  for (double temp = -59.0; temp < 80.0; temp += 3.7) {
    const double t_up = (temp + 60.0) / 5.0 * 60.0, t_down = up + (80.0 - temp) / 5.0 * 60.0;
    const Excitation ex = excite(p, {t_up, t_down}, {});
    const double w_up = ex.omega_ib_b[0].z(), w_down = ex.omega_ib_b[1].z();
    EXPECT_NEAR(ex.chamber_temp_c[0], temp, 1e-9);
    EXPECT_NEAR(ex.chamber_temp_c[1], temp, 1e-9);
    EXPECT_NEAR(w_up + w_down - 2.0 * earth::kRotationRate * std::sin(0.0), 0.0, 1e-12) << temp;
  }
}

TEST(Trajectories, SixPositionsGiveTable21EarthRateComponents) {
  const double lat = deg_to_rad(-25.86), w = earth::kRotationRate;
  const double wn = w * std::cos(lat), wd = -w * std::sin(lat);  // Omega_N, Omega_D (Omega_E = 0)
  const Eigen::Vector3d expected[6] = {{wn, 0, wd}, {wn, 0, -wd}, {wn, wd, 0}, {wn, -wd, 0}, {wd, 0, -wn}, {-wd, 0, wn}};
  for (int pos = 1; pos <= 6; ++pos) {
    StaticOptions o;
    o.duration_s = 10;
    o.position = pos;
    TableProfile p = static_profile(o);
    p.latitude_rad = lat;
    const Excitation ex = excite(p, {0.0, 5.0}, {});
    EXPECT_TRUE(ex.omega_ib_b[1].isApprox(expected[pos - 1], 1e-12)) << "position " << pos << ": " << ex.omega_ib_b[1].transpose();
    EXPECT_NEAR(ex.f_b[1].norm(), earth::normal_gravity(lat), 1e-12);
    const Eigen::Matrix3d c = mount_orientation(pos);
    EXPECT_NEAR(c.determinant(), 1.0, 1e-15);
  }
}

// Positions 7..10: a body diagonal along the table's Up axis, so a table rate W reaches each gyro as
// +-W / sqrt 3 with that diagonal's signs; proper rotations.
TEST(Trajectories, DiagonalPositionsTurnEveryGyroAtOneOverRootThreeOfTheTableRate) {
  const Eigen::Vector3d diagonals[4] = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
  for (int pos = 7; pos <= 10; ++pos) {
    const Eigen::Matrix3d c = mount_orientation(pos);
    EXPECT_NEAR(c.determinant(), 1.0, 1e-15) << pos;
    EXPECT_TRUE((c.transpose() * c).isApprox(Eigen::Matrix3d::Identity(), 1e-15)) << pos;
    StaticOptions o;
    o.duration_s = 10;
    o.position = pos;
    o.rate_radps = 0.5;
    TableProfile p = static_profile(o);
    p.latitude_rad = 0.0;
    ASSERT_EQ(p.check_limits(), "");
    const Excitation ex = excite(p, {0.0, 5.0}, {});
    // Table rate about Up: body rate 0.5 (d / sqrt 3) plus the Earth rate (at most 7.3e-5 rad/s).
    EXPECT_TRUE(ex.omega_ib_b[1].isApprox(0.5 * diagonals[pos - 7] / std::sqrt(3.0), 2e-4)) << pos << ": " << ex.omega_ib_b[1].transpose();
    EXPECT_NEAR(ex.f_b[1].dot(diagonals[pos - 7].normalized()), earth::normal_gravity(0.0), 1e-9) << pos;  // specific force up the diagonal
  }
  TableProfile bad;
  bad.segments.push_back({"x", 10.0, 25.0, 25.0, RateProfile::constant(0.0), 11});
  EXPECT_NE(bad.check_limits().find("not 1..10"), std::string::npos);
}

TEST(Trajectories, TableAngleIsTheExactIntegralOfTheTriangleRate) {
  // Position 1 (z down) at the equator: the Earth rate is along N, so its body x/y components rotate with
  // the table angle alpha; compare with a fine trapezoidal integral of the table rate.
  ScanOptions o = thesis_scan();
  o.rate_cycles_per_scan = 3.3;
  o.position = 1;
  TableProfile p = single_scan(o);
  std::vector<double> t;
  for (double s = 0; s <= 1000; s += 0.01) t.push_back(s);
  const Excitation ex = excite(p, t, {});
  double alpha = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    // Position 1: body z = Down, table rate about Up appears as -rate on body z.
    alpha += 0.5 * (-ex.omega_ib_b[k].z() - ex.omega_ib_b[k - 1].z()) * 0.01;
  }
  const Eigen::Vector3d e = ex.omega_ib_b.back();
  EXPECT_NEAR(std::atan2(-e.y(), e.x()), std::remainder(-alpha, 2 * std::numbers::pi), 1e-6);
}

TEST(Trajectories, CoilLagsTheChamberBySlopeTimesTau) {
  // After a long ramp the first-order lag trails by s * tau: 5 C/min x 300 s = 25 C.
  const TableProfile p = single_scan(thesis_scan());
  const Excitation ex = excite(p, {1500.0}, {0.0, {300.0}});
  EXPECT_NEAR(ex.chamber_temp_c[0] - ex.coil_temp_c[0], 25.0 * (1 - std::exp(-5.0)), 1e-9);
  EXPECT_NEAR(ex.coil_temp_rate_c_per_s[0], 5.0 / 60.0 * (1 - std::exp(-5.0)), 1e-12);
}

TEST(Trajectories, ThesisAliasingOf1000SamplesIsReproducible) {
  // Thesis s4.4: 1000 samples on a trajectory with 4, 8, 16 or 32 rate cycles put the samples on a few
  // repeated rate values (lines in the (T, omega) plane); 1111 samples break the pattern.
  ScanOptions o = thesis_scan();
  o.rate_cycles_per_scan = 16;
  const TableProfile p = dual_scan(o);
  auto distinct_rates = [&](std::size_t n) {
    const Excitation ex = excite(p, sample_times(p.duration_s(), {n, 0.0}), {});
    std::set<long long> values;
    for (const auto& w : ex.omega_ib_b) values.insert(std::llround(radps_to_dps(w.z()) * 100.0));
    return values.size();
  };
  // 1000 samples over 32 rate cycles: a phase step of 32/1000 = 4/125 cycle, so at most 125 distinct phases.
  const std::size_t aliased = distinct_rates(1000), fixed = distinct_rates(1111);
  EXPECT_LE(aliased, 126u);
  EXPECT_GT(fixed, 5 * aliased);
}

TEST(Trajectories, EveryKindWrittenAsAProgrammeReadsBackToTheSameExcitation) {
  for (const char* name : {"dual_scan", "single_scan", "test_4x16", "classical_soak", "static_2h"}) {
    const TrajectorySpec spec = load_trajectory_file(std::string("builtin:trajectories/") + name + ".yaml");
    const TrajectorySpec back = load_trajectory(ConfigNode::parse(programme_yaml(spec), "programme.yaml"));
    EXPECT_EQ(back.profile.kind, "programme");
    ASSERT_EQ(back.profile.segments.size(), spec.profile.segments.size()) << name;
    EXPECT_EQ(back.times().size(), spec.times().size()) << name;
    EXPECT_DOUBLE_EQ(back.profile.duration_s(), spec.profile.duration_s()) << name;
    std::vector<double> t;
    for (double s = 0; s < spec.profile.duration_s(); s += 7.3) t.push_back(s);
    const Excitation a = excite(spec.profile, t, {0.0, {300.0}}), b = excite(back.profile, t, {0.0, {300.0}});
    for (std::size_t k = 0; k < t.size(); ++k) {
      ASSERT_NEAR((a.omega_ib_b[k] - b.omega_ib_b[k]).norm(), 0.0, 1e-12) << name << " at " << t[k] << " s";
      ASSERT_NEAR(a.coil_temp_c[k], b.coil_temp_c[k], 1e-9) << name;
      ASSERT_EQ(a.position_id[k], b.position_id[k]) << name;
    }
  }
}

TEST(Trajectories, ProgrammeLimitsAreCheckedAsForTheHandMadeKinds) {
  const std::string head = "kind: programme\nchamber: {rate_limit_c_per_min: 5, min_c: -40, max_c: 85}\nsampling: {rate_hz: 1}\n";
  auto error_of = [&](const std::string& segments) -> std::string {
    try {
      load_trajectory(ConfigNode::parse(head + segments, "p.yaml"));
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of("segments:\n  - {duration_min: 10, chamber_c: [0, 50], rate_dps: 10}\n"), "");
  EXPECT_THAT(error_of("segments:\n  - {duration_min: 9, chamber_c: [0, 50], rate_dps: 10}\n"),
              ::testing::HasSubstr("exceeds the chamber's limit 5"));
  EXPECT_THAT(error_of("segments:\n  - {duration_min: 20, chamber_c: [0, -50], rate_dps: 10}\n"),
              ::testing::HasSubstr("outside the chamber range"));
  EXPECT_THAT(error_of("segments:\n  - {duration_min: 5, chamber_c: 10, rate_dps: 0}\n  - {duration_min: 5, chamber_c: 20, rate_dps: 0}\n"),
              ::testing::HasSubstr("segment 2 ('segment 2', starting at 5 min): the chamber starts at 20 C"));
  EXPECT_THAT(error_of("segments:\n  - {duration_min: 5, chamber_c: 10, rate_dps: {triangle: [10, -10], cycles: 2}}\n"),
              ::testing::HasSubstr("p.yaml:5"));
  EXPECT_THAT(error_of("segments:\n  - {duration_min: 5, chamber_c: 10, rate_dps: 0, speed: 3}\n"),
              ::testing::HasSubstr("unknown key 'speed'"));
}

}  // namespace
}  // namespace gyrosid
