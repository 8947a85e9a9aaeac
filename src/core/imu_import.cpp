#include "core/imu_import.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/imu_text_logs.h"
#include "core/progress.h"
#include "core/recording.h"
#include "core/rosbag_imu.h"
#include "core/triad_axes.h"
#include "core/ulog_reader.h"
#include "core/units.h"

namespace gyrosid {

namespace fs = std::filesystem;

std::string ImuImportOptions::validate() const {
  if (input.empty()) return "an input log is required (--input)";
  if (temp_c && !std::isfinite(*temp_c)) return "--temp-c must be finite";
  if (!stationary) {
    return "the log records no true rate, which a recording needs: if the IMU did not move, say so (--stationary: "
           "the true rate is written as zero and the metadata say so); a moving log needs a reference from elsewhere";
  }
  if (format == ImuLogFormat::imu_tk && !(gyro_scale_dps_per_count > 0)) {
    return "imu_tk logs are raw counts: give the gyro scale in deg/s per count (--gyro-scale-dps-per-count)";
  }
  if (format == ImuLogFormat::imu_tk && !accel_input.empty() && !(accel_scale_mps2_per_count > 0)) {
    return "an imu_tk accelerometer log needs its scale in m/s^2 per count (--accel-scale-mps2-per-count)";
  }
  if (format != ImuLogFormat::imu_tk && !accel_input.empty()) return "--accel-input is for imu_tk logs only";
  if (format == ImuLogFormat::rosbag && topic.empty()) return "a rosbag import needs the sensor_msgs/Imu topic (--topic, e.g. /imu)";
  if (format == ImuLogFormat::ulog && !topic.empty() && topic != "sensor_gyro" && topic != "sensor_combined") {
    return str_cat("--topic for a ulog log is sensor_gyro or sensor_combined, not '", topic, "'");
  }
  if (format != ImuLogFormat::rosbag && format != ImuLogFormat::ulog && !topic.empty()) return "--topic is for ulog and rosbag logs only";
  if (instance < 0 || instance > 255) return "--instance is a ULog multi_id, 0 to 255";
  if (format != ImuLogFormat::ulog && instance != 0) return "--instance is for ulog logs only";
  return "";
}

namespace {

// The rows of a triad recording from the samples, as they come: t_s exact from the integer stamps, the true rate
// zero (stationary), the gyro in deg/s, the temperature (the log's or the given constant), the specific force
// when the log has it. Holds one buffer of text and the histogram of the time steps.
class RowWriter {
 public:
  RowWriter(std::ostream& out, const ImuLogReader& reader, std::optional<double> temp_c)
      : out_(out), reader_(reader), temp_c_(temp_c), with_temp_(temp_c || reader.info().has_temperature),
        tps_(reader.info().ticks_per_second) {}

  void add(const ImuLogSample& s);
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }
  std::uint64_t rows() const { return rows_; }
  std::int64_t first_stamp() const { return first_; }
  const StepHistogram& steps() const { return steps_; }
  std::string header() const {
    std::string h = "t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps";
    if (with_temp_) h += ",temp_c";
    return reader_.info().has_accel ? h + ",accel_x_mps2,accel_y_mps2,accel_z_mps2" : h;
  }

 private:
  void number(double v) {
    char text[32];
    buffer_ += ',';
    buffer_.append(text, std::to_chars(text, text + sizeof text, v).ptr);
  }

  std::ostream& out_;
  const ImuLogReader& reader_;
  std::optional<double> temp_c_;
  bool with_temp_;  // a temperature is known (the log's or --temp-c); otherwise the recording has no temp_c
  std::int64_t tps_;
  std::string buffer_;
  std::uint64_t rows_ = 0;
  std::int64_t first_ = 0, last_ = 0;
  StepHistogram steps_;
};

void RowWriter::add(const ImuLogSample& s) {
  std::int64_t step = 0, since_first = 0;
  if (rows_ > 0 && (__builtin_sub_overflow(s.stamp, last_, &step) || step <= 0)) {
    fail(reader_.where(s.location), ": time stamp ", s.stamp, " does not follow ", last_, " (", reader_.info().time_source, " must increase)");
  }
  if (rows_ == 0) first_ = s.stamp;
  if (__builtin_sub_overflow(s.stamp, first_, &since_first)) fail(reader_.where(s.location), ": time stamp ", s.stamp, " is out of range");
  if (rows_ > 0) steps_.add(step);
  for (std::size_t k = 0; k < 3; ++k) {
    if (!std::isfinite(s.gyro_radps[k])) fail(reader_.where(s.location), ": gyro ", kTriadAxes[k], " is ", format_number(s.gyro_radps[k]), " (a recording's gyro must be finite)");
  }
  const double temp = temp_c_ ? *temp_c_ : s.temp_c;
  if (with_temp_ && !std::isfinite(temp)) {
    fail(reader_.where(s.location), ": the temperature (", reader_.info().temperature_source, ") is ", format_number(temp),
         "; give --temp-c to record a constant instead");
  }
  append_ticks_as_seconds(buffer_, since_first, tps_);
  buffer_ += ",0,0,0";
  for (std::size_t k = 0; k < 3; ++k) number(units::radps_to_dps(s.gyro_radps[k]));
  if (with_temp_) number(temp);
  if (reader_.info().has_accel) {
    for (std::size_t k = 0; k < 3; ++k) number(s.accel_mps2[k]);
  }
  buffer_ += '\n';
  last_ = s.stamp;
  ++rows_;
  if (buffer_.size() > (std::size_t{1} << 16)) flush();
}

// One line of metadata: printable, on one line.
std::string one_line(std::string text) {
  for (char& c : text) c = (c == '\n' || c == '\r') ? ' ' : c;
  return text;
}

std::vector<std::pair<std::string, std::string>> metadata(const ImuImportOptions& o, const ImuLogReader& reader, const RowWriter& w,
                                                          const SamplingSummary& sampling) {
  const ImuLogInfo& info = reader.info();
  std::vector<std::pair<std::string, std::string>> m;
  m.emplace_back("format", std::string(kRecordingFormat));
  std::string from = str_cat("imported from ", to_string(o.format), " log ", o.input);
  if (!o.accel_input.empty()) from += " and accelerometer log " + o.accel_input;
  if (o.format == ImuLogFormat::rosbag) from += ", topic " + o.topic;
  m.emplace_back("description", from);
  if (!info.sensor.empty()) m.emplace_back("sensor", info.sensor);
  if (sampling.rate_hz > 0) m.emplace_back("sample_rate_hz", format_significant(sampling.rate_hz, 10));
  m.emplace_back("sampling", sampling.description);
  m.emplace_back("time", str_cat("t_s is ", info.time_source, " less the first (", w.first_stamp(), "), exactly"));
  m.emplace_back("reference", "stationary (true rate written as zero; Earth rate not removed)");
  if (!o.temp_c && !info.has_temperature) {
    m.emplace_back("temperature", "none: the log records none and none was given (--temp-c); commands that need one refuse the recording");
  } else if (!o.temp_c) {
    m.emplace_back("temperature", "from the log: " + info.temperature_source);
  } else if (info.has_temperature) {
    m.emplace_back("temperature", str_cat("given: ", format_number(*o.temp_c), " C (replaces the log's ", info.temperature_source, ")"));
  } else {
    m.emplace_back("temperature", str_cat("given: ", format_number(*o.temp_c), " C (the log records none)"));
  }
  for (const auto& n : reader.notes()) m.emplace_back(n.key, n.value);
  for (auto& [key, value] : m) value = one_line(value);
  return m;
}

std::unique_ptr<ImuLogReader> open_reader(const ImuImportOptions& o, std::istream& in, std::istream* accel) {
  switch (o.format) {
    case ImuLogFormat::kalibr:
    case ImuLogFormat::euroc:
      return open_csv_imu_log(in, o.input, CsvImuDialect::kalibr);
    case ImuLogFormat::ros:
      return open_csv_imu_log(in, o.input, CsvImuDialect::ros);
    case ImuLogFormat::imu_tk:
      return open_imu_tk_log(in, o.input, accel, o.accel_input,
                             {o.gyro_scale_dps_per_count, o.gyro_offset_counts, o.accel_scale_mps2_per_count, o.accel_offset_counts});
    case ImuLogFormat::ulog:
      return open_ulog_gyro(in, o.input, {o.topic, o.instance});
    case ImuLogFormat::rosbag:
      return open_rosbag_imu(o.input, o.topic);
  }
  fail("import: unknown format");
}

}  // namespace

ImportResult import_rows(ImuLogReader& reader, const ImuImportOptions& o, std::ostream& rows, std::uint64_t total_bytes) {
  if (const std::string p = o.validate(); !p.empty()) fail("import: ", p);
  RowWriter w(rows, reader, o.temp_c);
  std::optional<Progress> progress;
  if (total_bytes > 0) progress.emplace(str_cat("import ", o.input), total_bytes);
  ImuLogSample s;
  while (reader.next(s)) {
    w.add(s);
    if (progress && (w.rows() & 0x3FFF) == 0) progress->update(reader.position());
  }
  if (w.rows() == 0) fail(o.input, ": no samples in the log");
  w.flush();
  if (progress) progress->finish();
  ImportResult r;
  r.rows = w.rows();
  r.sampling = summarize_sampling(w.steps(), reader.info().ticks_per_second);
  r.metadata = metadata(o, reader, w, r.sampling);
  r.header = w.header();
  for (const auto& n : reader.notes()) {
    if (n.warning) r.warnings.push_back(str_cat(o.input, ": ", n.key, ": ", one_line(n.value)));
  }
  return r;
}

ImportResult import_imu_log(const ImuImportOptions& o, const fs::path& out) {
  if (const std::string p = o.validate(); !p.empty()) fail("import: ", p);
  std::ifstream in, accel;
  if (o.format != ImuLogFormat::rosbag) {  // the ROS library opens its bag itself
    in.open(o.input, std::ios::binary);
    if (!in) fail(o.input, ": cannot open IMU log");
  }
  if (!o.accel_input.empty()) {
    accel.open(o.accel_input, std::ios::binary);
    if (!accel) fail(o.accel_input, ": cannot open accelerometer log");
  }
  const auto reader = open_reader(o, in, o.accel_input.empty() ? nullptr : &accel);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  // The rows go to a temporary file first: the metadata, which the whole stream determines, come first in the
  // recording. Removed however the import ends.
  const fs::path body = temporary_sibling(out);
  struct Remove {
    const fs::path& path;
    ~Remove() {
      std::error_code ignored;
      fs::remove(path, ignored);
    }
  } remove_body{body};
  ImportResult r;
  {
    std::ofstream rows(body, std::ios::binary | std::ios::trunc);
    if (!rows) fail(out.string(), ": cannot open for writing");
    std::error_code ec;
    const auto size = fs::file_size(o.input, ec);
    r = import_rows(*reader, o, rows, ec ? 0 : size);
    rows.close();
    if (!rows) fail(out.string(), ": write failed (disk full?)");
  }
  write_file_atomic(out, [&](std::ostream& file) {
    for (const auto& [key, value] : r.metadata) file << "# " << key << ": " << value << '\n';
    file << r.header << '\n';
    std::ifstream rows(body, std::ios::binary);
    file << rows.rdbuf();
  });
  return r;
}

}  // namespace gyrosid
