#include "core/recording.h"

#include "core/units.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/recording_reader.h"
#include "core/sample_timing.h"

namespace gyrosid {
namespace {

constexpr std::string_view kSingleRequired[] = {"t_s", "ref_rate_dps", "gyro_dps"};
constexpr std::string_view kTriadRates[] = {"ref_rate_x_dps", "ref_rate_y_dps", "ref_rate_z_dps",
                                            "gyro_x_dps",     "gyro_y_dps",     "gyro_z_dps"};
constexpr std::string_view kTriadTemps[] = {"temp_x_c", "temp_y_c", "temp_z_c"};

bool contains(const std::vector<std::string>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

bool Recording::has(std::string_view name) const {
  for (const auto& n : names_)
    if (n == name) return true;
  return false;
}

const std::vector<double>& Recording::column(std::string_view name) const {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return columns_[i];
  fail(source_, ": no column '", name, "' (columns: ", join(names_), ")");
}

void Recording::set_column(const std::string& name, std::vector<double> values) {
  if (!columns_.empty() && values.size() != rows()) {
    fail(source_, ": column '", name, "' has ", values.size(), " values, the recording has ", rows(), " rows");
  }
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) {
      columns_[i] = std::move(values);
      return;
    }
  }
  names_.push_back(name);
  columns_.push_back(std::move(values));
}

std::optional<std::string> Recording::meta(std::string_view key) const {
  for (const auto& [k, v] : metadata_)
    if (k == key) return v;
  return std::nullopt;
}

void Recording::set_meta(const std::string& key, const std::string& value) {
  for (auto& [k, v] : metadata_) {
    if (k == key) {
      v = value;
      return;
    }
  }
  metadata_.emplace_back(key, value);
}

RecordingKind recording_kind(const std::vector<std::string>& names) {
  for (auto n : kTriadRates)
    if (contains(names, n)) return RecordingKind::triad;
  return RecordingKind::single;
}

RecordingKind Recording::kind() const { return recording_kind(names_); }

std::string Recording::row_location(std::size_t row) const {
  if (header_line_ == 0) return str_cat(source_, " row ", row + 1);
  const auto jump = std::upper_bound(line_jumps_.begin(), line_jumps_.end(), row, [](std::size_t r, const auto& j) { return r < j.first; });
  if (jump == line_jumps_.begin()) return str_cat(source_, ":", header_line_ + 1 + row);
  return str_cat(source_, ":", std::prev(jump)->second + (row - std::prev(jump)->first));
}

std::vector<std::string> required_columns(RecordingKind kind, const std::vector<std::string>& names) {
  std::vector<std::string> out;
  if (kind == RecordingKind::single) {
    for (auto n : kSingleRequired) out.emplace_back(n);
    if (contains(names, "temp_c")) out.emplace_back("temp_c");
    return out;
  }
  out.emplace_back("t_s");
  for (auto n : kTriadRates) out.emplace_back(n);
  bool per_axis = false;
  for (auto n : kTriadTemps) per_axis = per_axis || contains(names, n);
  if (per_axis) {
    for (auto n : kTriadTemps) out.emplace_back(n);
  } else if (contains(names, "temp_c")) {
    out.emplace_back("temp_c");
  }
  return out;
}

std::vector<std::string> required_columns(RecordingKind kind, const Recording& recording) { return required_columns(kind, recording.names()); }

void require_column(const Recording& recording, std::string_view name, std::string_view why) {
  if (!recording.has(name)) fail(recording.source(), ": no column '", name, "': ", why, " (the recording has ", join(recording.names()), ")");
}

Recording read_recording(RecordingReader& reader, const std::vector<std::string>& columns) {
  Recording rec(reader.source());
  rec.metadata_ = reader.metadata();
  rec.header_line_ = reader.header_line();
  std::vector<std::size_t> keep;
  for (std::size_t c = 0; c < reader.names().size(); ++c) {
    if (!columns.empty() && !contains(columns, reader.names()[c])) continue;
    keep.push_back(c);
    rec.names_.push_back(reader.names()[c]);
  }
  rec.columns_.resize(keep.size());
  Progress progress("reading " + reader.source(), std::max<std::size_t>(reader.total_bytes(), 1));
  std::vector<double> row;
  std::size_t expected_line = reader.header_line() + 1;
  while (reader.next(row)) {
    const std::size_t r = reader.rows() - 1;
    if (reader.line() != expected_line) rec.line_jumps_.emplace_back(r, reader.line());
    expected_line = reader.line() + 1;
    if (r == 1000 && reader.total_bytes() > 0) {  // room for the rest, from the bytes the first rows took
      const double per_row = static_cast<double>(reader.bytes_read()) / 1001.0;
      const auto rows = static_cast<std::size_t>(1.02 * static_cast<double>(reader.total_bytes()) / per_row) + 16;
      for (auto& col : rec.columns_) col.reserve(rows);
    }
    for (std::size_t k = 0; k < keep.size(); ++k) rec.columns_[k].push_back(row[keep[k]]);
    if ((r & 0xffff) == 0 && reader.total_bytes() > 0) progress.update(reader.bytes_read());
  }
  progress.finish();
  return rec;
}

Recording read_recording(const std::filesystem::path& path, const std::vector<std::string>& columns) {
  RecordingReader reader(path);
  return read_recording(reader, columns);
}

Recording parse_recording(std::string_view text, const std::string& source) {
  RecordingReader reader(text, source);
  return read_recording(reader);
}

namespace {

void append_header(const Recording& recording, std::string& out) {
  out += "# format: ";
  out += kRecordingFormat;
  out += '\n';
  for (const auto& [key, value] : recording.metadata()) {
    if (key == "format") continue;
    out += "# " + key + ": " + value + "\n";
  }
  out += join(recording.names(), ",");
  out += '\n';
}

void append_rows(const std::vector<const std::vector<double>*>& cols, std::size_t begin, std::size_t end, std::string& out) {
  for (std::size_t r = begin; r < end; ++r) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c) out += ',';
      out += format_number((*cols[c])[r]);
    }
    out += '\n';
  }
}

std::vector<const std::vector<double>*> column_pointers(const Recording& recording) {
  std::vector<const std::vector<double>*> cols;
  for (const auto& name : recording.names()) cols.push_back(&recording.column(name));
  return cols;
}

}  // namespace

std::string format_recording(const Recording& recording) {
  std::string out;
  out.reserve(recording.rows() * recording.names().size() * 12 + 256);
  append_header(recording, out);
  append_rows(column_pointers(recording), 0, recording.rows(), out);
  return out;
}

void write_recording(const Recording& recording, const std::filesystem::path& path) {
  write_file_atomic(path, [&](std::ostream& out) {
    std::string text;
    append_header(recording, text);
    const auto cols = column_pointers(recording);
    constexpr std::size_t kRows = 4096;  // rows formatted per write: memory for one batch, not the file
    for (std::size_t r = 0; r < recording.rows(); r += kRows) {
      append_rows(cols, r, std::min(recording.rows(), r + kRows), text);
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

double uniform_sample_interval(const Recording& recording, std::string_view purpose) {
  const auto& t = recording.column("t_s");
  UniformStepCheck steps{std::string(purpose)};
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (const std::string e = steps.add(t[r]); !e.empty()) fail(recording.row_location(r), ": ", e);
  }
  return steps.interval(recording.source());
}

double median_sample_interval(std::span<const double> t_s) {
  if (t_s.size() < 2) return 1.0;
  std::vector<double> steps(t_s.size() - 1);
  for (std::size_t i = 1; i < t_s.size(); ++i) steps[i - 1] = t_s[i] - t_s[i - 1];
  const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  return *middle;
}

std::vector<double> rate_column_dph(const Recording& recording, const std::string& name) {
  const auto& column = recording.column(name);
  double scale = 0.0;
  if (name.size() > 4 && name.ends_with("_dps")) scale = units::kSecondsPerHour;
  if (name.size() > 4 && name.ends_with("_dph")) scale = 1.0;
  if (scale == 0.0) {
    fail(recording.source(), ": column '", name, "' is not a rate (its name must end in _dps or _dph)");
  }
  std::vector<double> out(column.size());
  for (std::size_t i = 0; i < column.size(); ++i) out[i] = column[i] * scale;
  return out;
}

}  // namespace gyrosid
