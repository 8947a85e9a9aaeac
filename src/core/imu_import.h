// Importers of the IMU logs users already have, into gyrosid triad recordings (docs/recording_format.md):
//
//   kalibr, euroc  Kalibr's imu CSV (timestamp, omega_x..z, alpha_x..z) or EuRoC MAV's imu0/data.csv
//                  (#timestamp [ns], w_RS_S_x [rad s^-1].., a_RS_S_x [m s^-2]..): columns by name (core/imu_text_logs.h)
//   ros            `rostopic echo -p` of sensor_msgs/Imu
//   imu_tk         IMU-TK's text files, raw counts scaled by the user's (count - offset) * scale
//   ulog           PX4 ULog: topic sensor_gyro (instance --instance), with its temperature; sensor_combined's
//                  gyro_rad when the log has no sensor_gyro (core/ulog_reader.h)
//   rosbag         ROS 1 bag, sensor_msgs/Imu on --topic (core/rosbag_imu.h; when built with librosbag-storage)
//
// The import streams: one sample at a time, rows written to a temporary file beside the output and moved into
// place with the metadata at the end (core/atomic_file.h), so memory does not grow with the log. What the
// recording says of its times is exact: t_s is the log's integer stamps less the first, as decimal seconds
// (core/sample_timing.h); `sample_rate_hz` is the median rate and `sampling` says whether the steps are uniform
// (and their jitter when not).
//
// Nothing is invented silently. No log records the true rate: it is written as zero only when the user states
// the IMU did not move (`stationary`; metadata "reference: stationary", Earth rate not removed). A log without
// a temperature (all but ULog's sensor_gyro) needs the constant the user gives (metadata "temperature: given");
// given for a log that has one, it replaces the log's and the metadata say so. Errors name the file, the line
// (or byte) and the column.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "core/imu_log.h"
#include "core/sample_timing.h"

namespace gyrosid {

enum class ImuLogFormat { kalibr, euroc, ros, imu_tk, ulog, rosbag };

template <>
struct EnumNames<ImuLogFormat> {
  static constexpr std::string_view kNoun = "IMU log format";
  static constexpr std::array<std::pair<ImuLogFormat, std::string_view>, 6> kTable{{{ImuLogFormat::kalibr, "kalibr"},
                                                                                     {ImuLogFormat::euroc, "euroc"},
                                                                                     {ImuLogFormat::ros, "ros"},
                                                                                     {ImuLogFormat::imu_tk, "imu_tk"},
                                                                                     {ImuLogFormat::ulog, "ulog"},
                                                                                     {ImuLogFormat::rosbag, "rosbag"}}};
};

struct ImuImportOptions {
  ImuLogFormat format = ImuLogFormat::kalibr;
  std::string input;                 // the log (imu_tk: the gyro file)
  std::string accel_input;           // imu_tk: the accelerometer file (optional)
  std::optional<double> temp_c;      // the temperature to record (required when the log has none)
  bool stationary = false;           // the IMU did not move: the true rate is zero
  std::string topic;                 // rosbag: the sensor_msgs/Imu topic; ulog: sensor_gyro or sensor_combined ("" = sensor_gyro if logged)
  int instance = 0;                  // ulog: the topic's multi_id
  double gyro_scale_dps_per_count = 0.0, gyro_offset_counts = 32768.0;      // imu_tk
  double accel_scale_mps2_per_count = 0.0, accel_offset_counts = 32768.0;  // imu_tk with accel_input
  std::string validate() const;
};

struct ImportResult {
  std::uint64_t rows = 0;
  SamplingSummary sampling;
  std::vector<std::pair<std::string, std::string>> metadata;  // every `# key: value` written
  std::string header;                                         // the column names row
  std::vector<std::string> warnings;                          // what the reader noted as a warning
};

// Imports the log into the recording `out` (written atomically).
ImportResult import_imu_log(const ImuImportOptions& options, const std::filesystem::path& out);

// The import over any reader: the recording's rows (no metadata, no header) to `rows`; the metadata and the
// header, which the whole stream determines, are returned. `total_bytes` sizes the progress lines (0: none).
ImportResult import_rows(ImuLogReader& reader, const ImuImportOptions& options, std::ostream& rows, std::uint64_t total_bytes = 0);

}  // namespace gyrosid
