// Importers of the IMU logs users already have, into gyrosid recordings (docs/recording_format.md, triad):
//
//   kalibr   Kalibr's imu CSV (kalibr_bagextractor): timestamp [ns], omega_x..z [rad/s], alpha_x..z [m/s^2]
//   ros      `rostopic echo -p` of sensor_msgs/Imu: %time [ns], field.angular_velocity.x..z [rad/s],
//            field.linear_acceleration.x..z [m/s^2] (other columns ignored)
//   imu_tk   IMU-TK's text files: one per sensor, rows "t x y z" (t in s, raw counts), gyro and optional accel
//            sharing time stamps; counts become units by (count - offset) * scale, both given by the user
//
// None of these formats records the true rate or a temperature, which a recording requires. The importer
// never invents them silently: the true rate is written as zero only when the user states the IMU did not
// move (`stationary`; the metadata then say "reference: stationary", Earth rate not removed), and the
// temperature is the constant the user gives (metadata "temperature: given"). Errors name the file, the line
// and the column.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "core/enum_names.h"
#include "core/recording.h"

namespace gyrosid {

enum class ImuLogFormat { kalibr, ros, imu_tk };

template <>
struct EnumNames<ImuLogFormat> {
  static constexpr std::string_view kNoun = "IMU log format";
  static constexpr std::array<std::pair<ImuLogFormat, std::string_view>, 3> kTable{
      {{ImuLogFormat::kalibr, "kalibr"}, {ImuLogFormat::ros, "ros"}, {ImuLogFormat::imu_tk, "imu_tk"}}};
};

struct ImuImportOptions {
  ImuLogFormat format = ImuLogFormat::kalibr;
  std::string input;                 // the log (imu_tk: the gyro file)
  std::string accel_input;           // imu_tk: the accelerometer file (optional)
  std::optional<double> temp_c;      // the temperature to record (required: the logs have none)
  bool stationary = false;           // the IMU did not move: the true rate is zero
  double gyro_scale_dps_per_count = 0.0, gyro_offset_counts = 32768.0;      // imu_tk
  double accel_scale_mps2_per_count = 0.0, accel_offset_counts = 32768.0;  // imu_tk with accel_input
  std::string validate() const;
};

Recording import_imu_log(const ImuImportOptions& options);

}  // namespace gyrosid
