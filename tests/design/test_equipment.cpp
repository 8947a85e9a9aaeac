// The equipment file (trajectory/equipment.h): the thesis's laboratory as the default, limits a programme
// must keep (heating and cooling apart, the table's acceleration), a design space that keeps them, and the
// set-point table a controller runs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "design/design_space.h"
#include "trajectory/equipment.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using units::dps_to_radps;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string write(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("gyrosid_equipment_" + name);
  std::ofstream(path) << text;
  return path.string();
}

TEST(Equipment, TheThesisLaboratoryIsTheDefault) {
  const Equipment e = load_equipment("builtin:equipment/thesis_lab.yaml");
  const ChamberLimits defaults;
  EXPECT_EQ(e.chamber.min_c, defaults.min_c);
  EXPECT_EQ(e.chamber.max_c, defaults.max_c);
  EXPECT_EQ(e.chamber.limit_c_per_min(true), defaults.limit_c_per_min(true));
  EXPECT_EQ(e.chamber.limit_c_per_min(false), defaults.limit_c_per_min(false));
  EXPECT_EQ(e.table.max_acceleration_radps2, INFINITY);
  EXPECT_EQ(e.table_max_rate_radps, INFINITY);
  EXPECT_THAT(error_of([] { load_equipment(write("typo.yaml", "kind: equipment\nchamber: {heating_c_per_mn: 3}\n")); }), HasSubstr("heating_c_per_mn"));
  EXPECT_THAT(error_of([] { load_equipment(write("neg.yaml", "kind: equipment\ntable: {max_acceleration_dps2: -1}\n")); }),
              HasSubstr("neg.yaml:2"));
  EXPECT_THAT(error_of([] { load_equipment(write("ring.yaml", "kind: equipment\ntable: {slip_ring: false}\n")); }), HasSubstr("slip ring"));
  EXPECT_THAT(error_of([] { load_equipment(write("kind.yaml", "kind: gyro\n")); }), HasSubstr("expected 'equipment'"));
}

TEST(Equipment, AProgrammeKeepsTheCoolingAndAccelerationLimitsApart) {
  const std::string head = "kind: programme\nchamber: {rate_limit_c_per_min: 5, cooling_limit_c_per_min: 2}\ntable: {max_acceleration_dps2: 10}\n"
                           "sampling: {rate_hz: 1}\nsegments:\n";
  // Heating at 4 C/min keeps the 5 C/min limit; cooling at 4 C/min breaks the 2 C/min one.
  const auto load = [&](const std::string& segments) { return load_trajectory(ConfigNode::parse(head + segments, "p.yaml")); };
  EXPECT_NO_THROW(load("  - {duration_min: 10, chamber_c: [0, 40], rate_dps: 0}\n"));
  EXPECT_THAT(error_of([&] { load("  - {duration_min: 10, chamber_c: [40, 0], rate_dps: 0}\n"); }), HasSubstr("cooling rate 4 C/min exceeds the chamber's limit 2"));
  // A triangle -50..50 deg/s with a 20-s period turns at 2 x 100 / 20 = 10 deg/s^2: at the limit; 10 s breaks it.
  EXPECT_NO_THROW(load("  - {duration_min: 1, chamber_c: 20, rate_dps: {triangle: [-50, 50], cycles: 3}}\n"));
  EXPECT_THAT(error_of([&] { load("  - {duration_min: 1, chamber_c: 20, rate_dps: {triangle: [-50, 50], cycles: 6}}\n"); }),
              HasSubstr("table acceleration 20 deg/s^2 exceeds the table's limit 10"));
}

TEST(Equipment, EveryDecodedDesignKeepsTheEquipmentsLimits) {
  design::DesignSpaceOptions o;
  o.budget_min = 60;
  o.chamber.rate_limit_c_per_min = 4.0;
  o.chamber.cooling_limit_c_per_min = 1.0;
  o.table_max_acceleration_dps2 = 3.0;
  o.table_max_rate_dps = 60.0;
  const design::DesignSpace space(o, -20.0, 60.0, dps_to_radps(100.0));
  EXPECT_NEAR(space.rate_max_radps(), dps_to_radps(60.0), 1e-15);  // the table caps the domain's 100 deg/s
  RandomStream rng(3, "equipment");
  int at_cooling_limit = 0, at_acceleration_limit = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::VectorXd v(space.box_dimension());
    for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = space.box_lower()(i) + rng.uniform() * (space.box_upper()(i) - space.box_lower()(i));
    const TableProfile p = space.decode_box(v);
    for (const auto& s : p.segments) {
      const double slope_c_per_min = (s.chamber_end_c - s.chamber_start_c) / (s.duration_s / 60.0);
      ASSERT_LE(slope_c_per_min, 4.0 * (1 + 1e-12));
      ASSERT_GE(slope_c_per_min, -1.0 * (1 + 1e-12));
      at_cooling_limit += slope_c_per_min < -1.0 + 1e-9;
      if (s.rate.shape == RateProfile::Shape::triangle) {
        const double accel = 2.0 * (s.rate.high_radps - s.rate.low_radps) * s.rate.cycles / s.duration_s;
        ASSERT_LE(accel, dps_to_radps(3.0) * (1 + 1e-12));
        at_acceleration_limit += accel > dps_to_radps(3.0) * (1 - 1e-9);
        ASSERT_LE(std::max(std::abs(s.rate.low_radps), std::abs(s.rate.high_radps)), dps_to_radps(60.0) * (1 + 1e-12));
      }
    }
  }
  EXPECT_GT(at_cooling_limit, 0);  // the limits bind: the test is not vacuous
  EXPECT_GT(at_acceleration_limit, 0);
}

TEST(Equipment, LinearInterpolationOfTheSetPointsIsTheProgramme) {
  const TrajectorySpec spec = load_trajectory(ConfigNode::parse(
      "kind: programme\nsampling: {rate_hz: 1}\nsegments:\n"
      "  - {duration_min: 7, chamber_c: [25, 0], rate_dps: {triangle: [-80, 40], cycles: 5.3, phase: 0.7}}\n"
      "  - {duration_min: 3, chamber_c: 0, rate_dps: 12, position: 1}\n"
      "  - {duration_min: 4.5, chamber_c: [0, 15], rate_dps: {triangle: [-10, 90], cycles: 2, phase: 0.25}}\n", "p.yaml"));
  std::istringstream csv(setpoint_table_csv(spec.profile));
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line, "t_s,chamber_setpoint_c,table_rate_dps,position");
  std::vector<std::array<double, 4>> rows;
  while (std::getline(csv, line)) {
    std::array<double, 4> r{};
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3]), 4) << line;
    rows.push_back(r);
  }
  ASSERT_NEAR(rows.back()[0], spec.profile.duration_s(), 1e-9);
  const PiecewiseLinear chamber = spec.profile.chamber_temperature();
  RandomStream rng(5, "setpoints");
  for (int k = 0; k < 2000; ++k) {
    const double t = rng.uniform() * spec.profile.duration_s();
    std::size_t i = 1;
    while (rows[i][0] < t) ++i;
    const double u = (t - rows[i - 1][0]) / (rows[i][0] - rows[i - 1][0]);
    double start = 0.0;
    std::size_t seg = 0;
    while (t > start + spec.profile.segments[seg].duration_s) start += spec.profile.segments[seg++].duration_s;
    const ProfileSegment& s = spec.profile.segments[seg];
    EXPECT_NEAR(rows[i - 1][2] + u * (rows[i][2] - rows[i - 1][2]), units::radps_to_dps(s.rate.at(t - start, s.duration_s)), 1e-9) << t;
    EXPECT_NEAR(rows[i - 1][1] + u * (rows[i][1] - rows[i - 1][1]), chamber.at(t), 1e-9) << t;
    EXPECT_EQ(rows[i][3], s.position) << t;
  }
}

}  // namespace
}  // namespace gyrosid
