// What every importer's reader gives (core/imu_import.h): the samples of one IMU stream, in time order, one at
// a time, so an import holds one sample and never the log. A sample keeps the log's own integer time stamp (in
// the log's ticks: ns for Kalibr/EuRoC/ROS, us for PX4 ULog), so times are differenced exactly, and its gyro
// output in rad/s (the unit of every format read here); specific force and temperature where the log has them.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace gyrosid {

struct ImuLogSample {
  std::int64_t stamp = 0;                       // in ImuLogInfo::ticks_per_second
  std::array<double, 3> gyro_radps{};
  std::array<double, 3> accel_mps2{NAN, NAN, NAN};  // NaN when the log has none
  double temp_c = NAN;                          // NaN when the log has none
  std::uint64_t location = 0;                   // source line (text logs) or byte offset (binary logs)
};

struct ImuLogInfo {
  std::int64_t ticks_per_second = 1'000'000'000;
  std::string time_source;    // what the stamps are, for the metadata ("timestamp [ns]", "sensor_gyro.timestamp_sample [us]")
  bool has_accel = false;
  bool has_temperature = false;
  std::string temperature_source;  // e.g. "sensor_gyro.temperature"
  std::string sensor;              // what the log says of the sensor, if anything (ULog: system and board)
};

struct ImuLogNote {
  std::string key, value;
  bool warning = false;
};

class ImuLogReader {
 public:
  virtual ~ImuLogReader() = default;
  const ImuLogInfo& info() const { return info_; }
  // The next sample; false at the end of the stream. Errors name the source and the line or byte.
  virtual bool next(ImuLogSample& sample) = 0;
  // "imu0.csv:17" or "log.ulg: byte 1234" for a sample's location.
  virtual std::string where(std::uint64_t location) const = 0;
  // How far the reading has got, in bytes of the source (for progress).
  virtual std::uint64_t position() const = 0;
  // What the reader had to note about the log once it ended (a truncated last message, dropouts, ...): each
  // becomes a `# key: value` metadata line of the recording, and a warning is also printed.
  virtual std::vector<ImuLogNote> notes() const { return {}; }

 protected:
  ImuLogInfo info_;
};

}  // namespace gyrosid
