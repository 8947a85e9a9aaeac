// ROS 1 bag import: sensor_msgs/Imu written by ROS's own serializer (rosbag_test_writer.h) read back exactly,
// on header.stamp (not the bag's receive time); wrong topics and types named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/imu_import.h"
#include "core/units.h"
#include "error_of.h"
#include "import_test_dir.h"
#include "rosbag_test_writer.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using testing_support::error_of;
using testing_support::PlantedImu;

class RosbagImport : public testing_support::ImportTest {
 protected:
  ImuImportOptions options(const std::string& topic) {
    ImuImportOptions o;
    o.format = ImuLogFormat::rosbag;
    o.input = (dir_ / "imu.bag").string();
    o.topic = topic;
    o.temp_c = 23.0;
    o.stationary = true;
    return o;
  }
};

std::vector<PlantedImu> planted(int n) {
  std::vector<PlantedImu> m;
  for (int k = 0; k < n; ++k) {
    PlantedImu p;
    p.sec = 1'700'000'000 + static_cast<std::uint32_t>(k / 400);
    p.nsec = static_cast<std::uint32_t>(k % 400) * 2'500'000;  // 400 Hz
    p.gyro_radps = {0.001 * k, -0.25, 1e-5};
    p.accel_mps2 = {0.0, 0.1 * k, -9.81};
    p.frame_id = k % 2 ? "imu" : "imu_link_with_a_longer_name";  // the header's string shifts every later field
    m.push_back(p);
  }
  return m;
}

TEST_F(RosbagImport, SensorMsgsImuReadsBackExactlyOnItsHeaderStamps) {
  testing_support::write_imu_bag(options("/imu").input, "/imu", planted(801));
  const Recording r = import(options("/imu"));
  ASSERT_EQ(r.rows(), 801u);
  EXPECT_EQ(r.column("t_s")[1], 0.0025);
  EXPECT_EQ(r.column("t_s")[800], 2.0);
  EXPECT_EQ(data_line(3).substr(0, 7), "0.0075,");
  EXPECT_EQ(r.column("gyro_x_dps")[7], units::radps_to_dps(0.001 * 7));
  EXPECT_EQ(r.column("gyro_y_dps")[8], units::radps_to_dps(-0.25));
  EXPECT_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(1e-5));
  EXPECT_EQ(r.column("accel_y_mps2")[9], 0.1 * 9);
  EXPECT_EQ(r.column("accel_z_mps2")[4], -9.81);
  EXPECT_EQ(r.meta("sample_rate_hz").value_or(""), "400");
  EXPECT_EQ(r.meta("time").value_or(""), "t_s is /imu header.stamp [ns] less the first (1700000000000000000), exactly");
}

TEST_F(RosbagImport, WrongTopicsAndTypesAreNamed) {
  testing_support::write_imu_bag(options("/imu").input, "/imu", planted(3));
  EXPECT_THAT(error_of([&] { import(options("/gyro")); }), HasSubstr("imu.bag: no messages on topic '/gyro'; the bag has "));
  EXPECT_THAT(error_of([&] { import(options("/gyro")); }), HasSubstr("/imu (sensor_msgs/Imu)"));
  EXPECT_THAT(error_of([&] { import(options("/temperature")); }),
              HasSubstr("topic '/temperature' carries sensor_msgs/Temperature"));
  ImuImportOptions o = options("/imu");
  o.input = write("not.bag", "#ROSBAG V2.0\nnot really");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("not.bag: cannot read the bag"));
  o.topic = "";
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("--topic"));
}

}  // namespace
}  // namespace gyrosid
