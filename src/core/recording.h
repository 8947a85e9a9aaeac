// Recordings in the gyrosid recording format, version 1 (docs/recording_format.md): what a rate table, a thermal
// chamber and a gyro (or triad) produced together, or what the simulator produces in their place.
//
// Columns are held by name in file units (the unit is the name's suffix: _s, _dps, _dph, _c, _mps2, ...);
// conversion to SI happens in the layer that interprets a column. Unknown columns are auxiliary channels
// and are kept; unknown metadata keys are kept.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"

namespace gyrosid {

enum class RecordingKind { single, triad };

template <>
struct EnumNames<RecordingKind> {
  static constexpr std::string_view kNoun = "recording kind";
  static constexpr std::array<std::pair<RecordingKind, std::string_view>, 2> kTable{
      {{RecordingKind::single, "single"}, {RecordingKind::triad, "triad"}}};
};

inline constexpr std::string_view kRecordingFormat = "gyrosid-recording/1";

class RecordingReader;  // core/recording_reader.h

class Recording {
 public:
  Recording() = default;
  explicit Recording(std::string source) : source_(std::move(source)) {}

  // Where the data came from ("rec.csv" or "<simulation>"), used in every error message.
  const std::string& source() const { return source_; }
  std::size_t rows() const { return columns_.empty() ? 0 : columns_.front().size(); }

  const std::vector<std::string>& names() const { return names_; }
  bool has(std::string_view name) const;
  const std::vector<double>& column(std::string_view name) const;  // Error naming the file if absent
  // Adds a column or replaces one of the same name; its length must equal rows() (unless empty).
  void set_column(const std::string& name, std::vector<double> values);

  const std::vector<std::pair<std::string, std::string>>& metadata() const { return metadata_; }
  std::optional<std::string> meta(std::string_view key) const;
  void set_meta(const std::string& key, const std::string& value);

  RecordingKind kind() const;
  // "rec.csv:17" for data row `row` (0-based) of a file that was read; "<simulation> row 17" otherwise.
  std::string row_location(std::size_t row) const;
  // Source line of the header row (0 when not read from a file).
  std::size_t header_line() const { return header_line_; }

 private:
  friend Recording read_recording(RecordingReader& reader, const std::vector<std::string>& columns);
  std::string source_ = "<memory>";
  std::vector<std::pair<std::string, std::string>> metadata_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
  // Source lines of the rows read from a file: row r is on line header_line_ + 1 + r until the first jump;
  // a jump (row, line) - after a comment or blank line inside the data - restarts the count at that row.
  std::vector<std::pair<std::size_t, std::size_t>> line_jumps_;
  std::size_t header_line_ = 0;
};

// Reads and validates a recording, keeping `columns` only (every column when empty; the others are read and
// checked, not stored; a requested column the file lacks is left out). Every violation of
// docs/recording_format.md is an Error naming the file, the line and the column.
Recording read_recording(const std::filesystem::path& path, const std::vector<std::string>& columns = {});
Recording read_recording(RecordingReader& reader, const std::vector<std::string>& columns = {});
Recording parse_recording(std::string_view text, const std::string& source);

// Writes `# format: gyrosid-recording/1`, the other metadata, the header and the rows (shortest round-trip
// numbers), atomically.
void write_recording(const Recording& recording, const std::filesystem::path& path);
std::string format_recording(const Recording& recording);

// A recording with any triad rate column (ref_rate_x_dps ... gyro_z_dps) is a triad, else a single gyro.
RecordingKind recording_kind(const std::vector<std::string>& names);
// Columns a recording of this kind with these columns must have, none of them nan: t_s and the rate
// columns, and the temperature where it is recorded (temp_c; a triad's temp_x_c, temp_y_c, temp_z_c all
// three once one is there). The temperature is optional: static noise logs have no thermometer.
std::vector<std::string> required_columns(RecordingKind kind, const std::vector<std::string>& names);
std::vector<std::string> required_columns(RecordingKind kind, const Recording& recording);

// Error naming the recording and the column when `name` is not recorded; `why` says what needs it
// ("calibrate's models take the temperature as an input").
void require_column(const Recording& recording, std::string_view name, std::string_view why);

// The sample interval of a uniformly sampled recording, in seconds. Commands that need uniform sampling
// call this; a non-uniform recording is an Error (naming `purpose` and the first offending row), never
// resampled silently. Relative tolerance on each step: 1e-4.
double uniform_sample_interval(const Recording& recording, std::string_view purpose);

// The median step of the sample times t_s, in seconds: the typical interval of a recording with gaps or
// jitter (1 when there are fewer than two samples).
double median_sample_interval(std::span<const double> t_s);

// A rate column in deg/h, whatever its suffix (_dps or _dph); Error naming the column for other columns.
std::vector<double> rate_column_dph(const Recording& recording, const std::string& name);

}  // namespace gyrosid
