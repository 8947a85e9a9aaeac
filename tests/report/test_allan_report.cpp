// The Kalibr noise file: Allan coefficients converted to Kalibr's continuous-time units.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "report/allan_report.h"

namespace gyrosid {
namespace {

TEST(KalibrNoise, DensitiesInRadiansPerSecondRootHertz) {
  CompositeNoise fit;
  fit.white = 10.0;       // (deg/h) sqrt(s): white noise of 10 deg/h at 1 Hz, N = 1/6 deg/sqrt(h)
  fit.random_walk = 0.6;  // (deg/h)/sqrt(s): K = 36 (deg/h)/sqrt(h)
  const auto path = std::filesystem::temp_directory_path() / "gyrosid_kalibr_imu.yaml";
  write_kalibr_noise_yaml(path, fit, 200.0, "test");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(path);
  const double pi = std::acos(-1.0);
  // 10 deg/h = 10/3600 deg/s, times sqrt(s): rad/s/sqrt(Hz).
  double density = 0, walk = 0, rate = 0;
  std::string line;
  while (std::getline(text, line)) {
    if (line.rfind("gyroscope_noise_density:", 0) == 0) density = std::stod(line.substr(24));
    if (line.rfind("gyroscope_random_walk:", 0) == 0) walk = std::stod(line.substr(22));
    if (line.rfind("update_rate:", 0) == 0) rate = std::stod(line.substr(12));
  }
  EXPECT_NEAR(density, 10.0 / 3600.0 * pi / 180.0, 1e-18);
  EXPECT_NEAR(walk, 0.6 / 3600.0 * pi / 180.0, 1e-18);
  EXPECT_EQ(rate, 200.0);
  EXPECT_THAT(text.str(), ::testing::HasSubstr("sqrt(update_rate)"));
}

}  // namespace
}  // namespace gyrosid
