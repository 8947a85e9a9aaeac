#include "core/imu_import.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

std::string ImuImportOptions::validate() const {
  if (input.empty()) return "an input log is required (--input)";
  if (!temp_c) return "the log records no temperature: give the temperature to record (--temp-c)";
  if (!std::isfinite(*temp_c)) return "--temp-c must be finite";
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
  return "";
}

namespace {

struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  std::vector<std::string> first_cells;  // column 0 as written (integer nanosecond stamps exceed a double's precision)
  std::vector<std::size_t> lines;
};

// A delimited numeric table; `header` says whether the first non-comment line names the columns.
Table read_table(const std::string& path, char delimiter, bool header, std::size_t width_without_header) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, ": cannot open IMU log");
  Table t;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    std::vector<std::string> cells;
    if (delimiter == ' ') {
      std::istringstream ss(line);
      for (std::string c; ss >> c;) cells.push_back(c);
    } else {
      std::stringstream ss(line);
      for (std::string c; std::getline(ss, c, delimiter);) cells.push_back(c);
    }
    if (t.names.empty() && header) {
      t.names = cells;
      t.columns.resize(cells.size());
      continue;
    }
    if (t.names.empty()) {
      for (std::size_t c = 0; c < width_without_header; ++c) t.names.push_back(std::to_string(c));
      t.columns.resize(width_without_header);
    }
    if (cells.size() != t.names.size()) fail(path, ":", line_no, ": row has ", cells.size(), " values, expected ", t.names.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = parse_c_double(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0') fail(path, ":", line_no, ": column '", t.names[c], "': '", cells[c], "' is not a number");
      t.columns[c].push_back(v);
    }
    t.first_cells.push_back(cells.front());
    t.lines.push_back(line_no);
  }
  if (t.lines.empty()) fail(path, ": no data rows");
  return t;
}

const std::vector<double>& column(const Table& t, const std::string& name, const std::string& path) {
  for (std::size_t c = 0; c < t.names.size(); ++c) {
    if (t.names[c] == name) return t.columns[c];
  }
  fail(path, ": missing column '", name, "'");
}

// The recording's columns in the format's own units: t_s, gyro rad/s, accel m/s^2 (empty when absent).
struct Samples {
  std::vector<double> t_s;
  std::vector<std::size_t> lines;  // source line of each sample
  std::array<std::vector<double>, 3> gyro_radps, accel_mps2;
};

Samples read_kalibr_or_ros(const ImuImportOptions& o) {
  const bool ros = o.format == ImuLogFormat::ros;
  const Table t = read_table(o.input, ',', true, 0);
  const std::string time = ros ? "%time" : "timestamp";
  if (t.names.front() != time) fail(o.input, ": the first column must be '", time, "' (integer nanoseconds)");
  const char* axes[] = {"x", "y", "z"};
  Samples s;
  // Nanoseconds since the epoch need 61 bits: differences are taken in integers, then converted.
  const long long t0 = std::stoll(t.first_cells.front());
  for (std::size_t i = 0; i < t.first_cells.size(); ++i) {
    char* end = nullptr;
    const long long ns = std::strtoll(t.first_cells[i].c_str(), &end, 10);
    if (*end != '\0') fail(o.input, ":", t.lines[i], ": '", t.first_cells[i], "' is not an integer time stamp in nanoseconds");
    s.t_s.push_back(static_cast<double>(ns - t0) * 1e-9);
  }
  s.lines = t.lines;
  for (int k = 0; k < 3; ++k) {
    const std::string w = ros ? std::string("field.angular_velocity.") + axes[k] : std::string("omega_") + axes[k];
    const std::string a = ros ? std::string("field.linear_acceleration.") + axes[k] : std::string("alpha_") + axes[k];
    s.gyro_radps[static_cast<std::size_t>(k)] = column(t, w, o.input);
    s.accel_mps2[static_cast<std::size_t>(k)] = column(t, a, o.input);
  }
  return s;
}

Samples read_imu_tk(const ImuImportOptions& o) {
  const Table g = read_table(o.input, ' ', false, 4);
  Samples s;
  s.t_s = g.columns[0];
  s.lines = g.lines;
  for (std::size_t k = 0; k < 3; ++k) {
    for (double c : g.columns[k + 1]) s.gyro_radps[k].push_back(units::dps_to_radps((c - o.gyro_offset_counts) * o.gyro_scale_dps_per_count));
  }
  if (!o.accel_input.empty()) {
    const Table a = read_table(o.accel_input, ' ', false, 4);
    if (a.columns[0] != g.columns[0]) fail(o.accel_input, ": its time stamps differ from the gyro log's (", o.input, ")");
    for (std::size_t k = 0; k < 3; ++k) {
      for (double c : a.columns[k + 1]) s.accel_mps2[k].push_back((c - o.accel_offset_counts) * o.accel_scale_mps2_per_count);
    }
  }
  return s;
}

}  // namespace

Recording import_imu_log(const ImuImportOptions& o) {
  if (const std::string p = o.validate(); !p.empty()) fail("import: ", p);
  const Samples s = o.format == ImuLogFormat::imu_tk ? read_imu_tk(o) : read_kalibr_or_ros(o);
  for (std::size_t i = 1; i < s.t_s.size(); ++i) {
    if (!(s.t_s[i] > s.t_s[i - 1])) fail(o.input, ":", s.lines[i], ": the time stamp does not increase");
  }
  Recording rec(o.input);
  rec.set_meta("format", std::string(kRecordingFormat));
  rec.set_meta("description", str_cat("imported from ", to_string(o.format), " log ", o.input));
  rec.set_meta("reference", "stationary (true rate written as zero; Earth rate not removed)");
  rec.set_meta("temperature", str_cat("given: ", format_number(*o.temp_c), " C (the log records none)"));
  const std::size_t n = s.t_s.size();
  rec.set_column("t_s", s.t_s);
  const char* axes[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k) rec.set_column(str_cat("ref_rate_", axes[k], "_dps"), std::vector<double>(n, 0.0));
  for (std::size_t k = 0; k < 3; ++k) {
    std::vector<double> dps;
    for (double w : s.gyro_radps[k]) dps.push_back(units::radps_to_dps(w));
    rec.set_column(str_cat("gyro_", axes[k], "_dps"), dps);
  }
  rec.set_column("temp_c", std::vector<double>(n, *o.temp_c));
  if (!s.accel_mps2[0].empty()) {
    for (std::size_t k = 0; k < 3; ++k) rec.set_column(str_cat("accel_", axes[k], "_mps2"), s.accel_mps2[k]);
  }
  // Through the format's own checks (increasing t_s, finite values), with the log's name in the messages.
  return parse_recording(format_recording(rec), o.input + " (imported)");
}

}  // namespace gyrosid
