// Readers of the text IMU logs people have (core/imu_log.h), one row at a time:
//
//   Kalibr / EuRoC CSV   one header row, then rows of integer nanosecond stamps and SI values. Columns are found by
//                        name in any order, unknown columns ignored; the header's leading '#' and each name's
//                        bracketed unit are read, the unit checked:
//                          Kalibr (kalibr_bagextractor)  timestamp, omega_x..z, alpha_x..z
//                          EuRoC MAV (imu0/data.csv)     #timestamp [ns], w_RS_S_x [rad s^-1] .., a_RS_S_x [m s^-2] ..
//                        The accelerometer columns are optional (all three or none).
//   ROS `rostopic echo -p` of sensor_msgs/Imu: %time [ns], field.angular_velocity.x..z [rad/s],
//                        field.linear_acceleration.x..z [m/s^2]; every other column ignored.
//   IMU-TK               whitespace-separated rows "t x y z": t in seconds (read as decimal, to the nanosecond),
//                        x y z raw counts, converted by (count - offset) * scale; an optional accelerometer file
//                        with the same time stamps, read in step.
//
// Errors name the file, the line and the column (a missing column at the header's line).
#pragma once

#include <cstdint>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/imu_log.h"

namespace gyrosid {

enum class CsvImuDialect { kalibr, ros };  // kalibr reads the EuRoC header too

std::unique_ptr<ImuLogReader> open_csv_imu_log(std::istream& in, std::string source, CsvImuDialect dialect);

struct ImuTkScaling {
  double gyro_scale_dps_per_count = 0.0, gyro_offset_counts = 32768.0;
  double accel_scale_mps2_per_count = 0.0, accel_offset_counts = 32768.0;
};

// `accel` may be null (gyro only).
std::unique_ptr<ImuLogReader> open_imu_tk_log(std::istream& gyro, std::string gyro_source, std::istream* accel,
                                              std::string accel_source, const ImuTkScaling& scaling);

// Decimal seconds ("2.9840000e-02", "12.5", "-3") as integer nanoseconds, rounded half away from zero below
// the nanosecond; nullopt when the text is not a decimal number or overflows.
std::optional<std::int64_t> decimal_seconds_to_ns(std::string_view text);

}  // namespace gyrosid
