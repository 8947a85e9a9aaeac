// A ROS 1 bag written by ROS's own code (rosbag_storage, and sensor_msgs' generated message types), for the
// rosbag importer's tests: what the importer decodes by hand is checked against ROS's serializer. Plain C++ in
// this header; the ROS types stay in rosbag_test_writer.cpp (C++17: ROS 1's generated headers do not build as
// C++20).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gyrosid::testing_support {

struct PlantedImu {
  std::uint32_t sec = 0, nsec = 0;   // header.stamp
  std::array<double, 3> gyro_radps{}, accel_mps2{};
  std::string frame_id = "imu_link";
};

// The messages on `topic` as sensor_msgs/Imu (each recorded by the bag 1 ms after its stamp), and one
// sensor_msgs/Temperature on "/temperature".
void write_imu_bag(const std::string& path, const std::string& topic, const std::vector<PlantedImu>& messages);

}  // namespace gyrosid::testing_support
