// ROS 1 bag IMU data as an IMU stream (core/imu_log.h): the sensor_msgs/Imu messages of one topic, read with
// Debian's rosbag_storage library (librosbag-storage-dev; optional at build time - without it this reader is an
// Error that says so). Time: each message's header.stamp (the sensor's time, integer ns), not the time the bag
// recorded it. sensor_msgs/Imu has no temperature.
//
// Memory: the library holds the bag's message index (one entry per message, tens of bytes each); the
// messages themselves are read one at a time.
#pragma once

#include <memory>
#include <string>

#include "core/imu_log.h"

namespace gyrosid {

bool rosbag_available();
std::unique_ptr<ImuLogReader> open_rosbag_imu(const std::string& path, const std::string& topic);

}  // namespace gyrosid
