// The prior over sensors (sensor/sensor_prior.h): listed members, draws around them by the stated laws, the
// degenerate prior of one sensor config, and errors that name the file and the key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/random.h"
#include "sensor/sensor_prior.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class SensorPriorFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gyrosid_prior_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  std::string error_of(const std::string& path) {
    try {
      load_sensor_prior(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

const GyroSensor& gyro(const SensorPriorMember& m) { return std::get<GyroSensor>(m.sensor); }

constexpr const char* kTwoMembers =
    "format: gyrosid-prior/1\n"
    "name: two units\n"
    "members:\n"
    "  - {sensor: builtin:sensors/open_loop_fog.yaml, weight: 2}\n"
    "  - sensor: builtin:sensors/open_loop_fog.yaml\n"
    "    draws:\n"
    "      count: 3\n"
    "      seed: 7\n"
    "      vary:\n"
    "        bias.constant_dph: {sd: 2}\n"
    "        scale_factor.surface.error_ppm: {log_sd: 0.3}\n";

TEST_F(SensorPriorFile, DrawsMoveEachVariedPathByOneDrawOfItsLaw) {
  const SensorPrior prior = load_sensor_prior(write("p.yaml", kTwoMembers));
  ASSERT_EQ(prior.members.size(), 5u);  // two listed, three drawn around the second
  EXPECT_EQ(prior.name, "two units");
  EXPECT_DOUBLE_EQ(prior.total_weight(), 2.0 + 1.0 + 3 * 1.0);  // draws take their parent's weight
  EXPECT_EQ(prior.members[2].name, "open-loop FOG (reference) (draw 1)");
  const GyroSensor& parent = gyro(prior.members[1]);
  for (int j = 1; j <= 3; ++j) {
    const GyroSensor& d = gyro(prior.members[static_cast<std::size_t>(1 + j)]);
    // bias.constant_dph + 2 z (deg/h), z the documented stream's normal deviate.
    const double zb = RandomStream(7, "prior/1/" + std::to_string(j) + "/bias.constant_dph").normal();
    EXPECT_NEAR(d.errors.bias_radps - parent.errors.bias_radps, 2.0 * zb * M_PI / 180.0 / 3600.0, 1e-15) << j;
    // The whole surface by one factor exp(0.3 z): the ratio is the same at every (T, omega).
    const double zs = RandomStream(7, "prior/1/" + std::to_string(j) + "/scale_factor.surface.error_ppm").normal();
    for (double t : {-40.0, 10.0, 55.0}) {
      for (double w : {-1.2, 0.3, 1.5}) {
        const double ratio = d.errors.scale_factor_error(t, w).value / parent.errors.scale_factor_error(t, w).value;
        EXPECT_NEAR(ratio, std::exp(0.3 * zs), 1e-9) << j << " " << t << " " << w;
      }
    }
    // What is not varied is the parent's.
    EXPECT_EQ(d.noise.arw_rad_rt_s, parent.noise.arw_rad_rt_s);
    EXPECT_EQ(d.thermal.tau_s, parent.thermal.tau_s);
  }
  // The same file, the same members; draws differ from each other.
  const SensorPrior again = load_sensor_prior(write("q.yaml", kTwoMembers));
  for (std::size_t k = 0; k < prior.members.size(); ++k) EXPECT_EQ(gyro(again.members[k]).errors.bias_radps, gyro(prior.members[k]).errors.bias_radps);
  EXPECT_NE(gyro(prior.members[2]).errors.bias_radps, gyro(prior.members[3]).errors.bias_radps);
}

TEST_F(SensorPriorFile, ASensorConfigIsThePriorOfThatOneSensor) {
  const SensorPrior prior = load_sensor_prior("builtin:sensors/open_loop_fog.yaml");
  ASSERT_EQ(prior.members.size(), 1u);
  EXPECT_EQ(prior.members[0].weight, 1.0);
  EXPECT_EQ(prior.members[0].name, "open-loop FOG (reference)");
  EXPECT_EQ(gyro(prior.members[0]).noise.arw_rad_rt_s, std::get<GyroSensor>(load_sensor_file("builtin:sensors/open_loop_fog.yaml")).noise.arw_rad_rt_s);
}

TEST_F(SensorPriorFile, ErrorsNameTheFileTheKeyAndTheMember) {
  const std::string head = "format: gyrosid-prior/1\nmembers:\n  - sensor: builtin:sensors/open_loop_fog.yaml\n";
  const std::string missing = write("missing.yaml", head + "    draws: {count: 2, vary: {noise.gauss_markov.0.tau_s: {log_sd: 0.5}}}\n");
  EXPECT_THAT(error_of(missing), HasSubstr("missing.yaml:4"));
  EXPECT_THAT(error_of(missing), HasSubstr("builtin:sensors/open_loop_fog.yaml has no number or list of numbers at 'noise.gauss_markov.0.tau_s'"));
  EXPECT_THAT(error_of(write("both.yaml", head + "    draws: {count: 2, vary: {thermal.tau_s: {sd: 1, log_sd: 0.5}}}\n")),
              HasSubstr("give exactly one of sd"));
  EXPECT_THAT(error_of(write("weight.yaml", "format: gyrosid-prior/1\nmembers:\n  - {sensor: builtin:sensors/open_loop_fog.yaml, weight: 0}\n")),
              HasSubstr("weight.yaml:3"));
  EXPECT_THAT(error_of(write("format.yaml", "format: gyrosid-prior/2\nmembers: []\n")), HasSubstr("expected 'gyrosid-prior/1'"));
  EXPECT_THAT(error_of(write("empty.yaml", "format: gyrosid-prior/1\nmembers: []\n")), HasSubstr("non-empty list"));
  EXPECT_THAT(error_of(write("typo.yaml", head + "    wieght: 2\n")), HasSubstr("wieght"));
  EXPECT_THAT(error_of(write("nofile.yaml", "format: gyrosid-prior/1\nmembers:\n  - sensor: none.yaml\n")), HasSubstr("none.yaml"));
}

}  // namespace
}  // namespace gyrosid
