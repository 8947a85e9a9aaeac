#include "rosbag_test_writer.h"

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Temperature.h>

namespace gyrosid::testing_support {

void write_imu_bag(const std::string& path, const std::string& topic, const std::vector<PlantedImu>& messages) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (const auto& p : messages) {
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(p.sec, p.nsec);
    m.header.frame_id = p.frame_id;
    m.orientation.w = 1.0;
    m.angular_velocity.x = p.gyro_radps[0], m.angular_velocity.y = p.gyro_radps[1], m.angular_velocity.z = p.gyro_radps[2];
    m.linear_acceleration.x = p.accel_mps2[0], m.linear_acceleration.y = p.accel_mps2[1], m.linear_acceleration.z = p.accel_mps2[2];
    m.angular_velocity_covariance[0] = -1.0;
    bag.write(topic, m.header.stamp + ros::Duration(0, 1'000'000), m);
  }
  sensor_msgs::Temperature t;
  t.header.stamp = ros::Time(messages.empty() ? 1 : messages.front().sec, 0);
  t.temperature = 24.5;
  bag.write("/temperature", t.header.stamp, t);
}

}  // namespace gyrosid::testing_support
