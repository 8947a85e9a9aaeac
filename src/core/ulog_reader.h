// PX4 ULog gyro data as an IMU stream (core/imu_log.h), over the container of core/ulog_format.h.
//
// Topics (uORB messages, logged by PX4's logger):
//   sensor_gyro       timestamp, timestamp_sample [us], x, y, z [rad/s], temperature [degC], one instance per
//                     gyro (multi_id). The time is timestamp_sample (when the gyro sampled) where the format has
//                     it, else timestamp (when the driver published). This is the data PX4's own thermal
//                     calibration fits its per-axis cubic on.
//   sensor_combined   timestamp [us], gyro_rad[3] [rad/s]: the vehicle's primary gyro, no temperature.
// By default sensor_gyro is read when the log holds data of the chosen instance, else sensor_combined.
//
// Two passes over the file: the first learns the formats and subscriptions and counts each subscription's data
// (so the topic is chosen knowing what the log holds, and an absent one is named with what is there); the
// second decodes the chosen topic's data messages one at a time. Dropouts ('O') are counted and noted with
// their total duration: the samples on either side are kept, and the gap shows in the time steps.
#pragma once

#include <istream>
#include <memory>
#include <string>

#include "core/imu_log.h"

namespace gyrosid {

struct UlogGyroChoice {
  std::string topic;  // "sensor_gyro", "sensor_combined" or "" (sensor_gyro if logged, else sensor_combined)
  int instance = 0;   // the topic's multi_id
};

std::unique_ptr<ImuLogReader> open_ulog_gyro(std::istream& in, std::string source, const UlogGyroChoice& choice);

}  // namespace gyrosid
