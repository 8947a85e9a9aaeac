#include "core/recording.h"

#include "core/units.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/error.h"

namespace gyrosid {
namespace {

constexpr std::string_view kSingleRequired[] = {"t_s", "ref_rate_dps", "temp_c", "gyro_dps"};
constexpr std::string_view kTriadRates[] = {"ref_rate_x_dps", "ref_rate_y_dps", "ref_rate_z_dps",
                                            "gyro_x_dps",     "gyro_y_dps",     "gyro_z_dps"};
constexpr std::string_view kTriadTemps[] = {"temp_x_c", "temp_y_c", "temp_z_c"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// "# key: value" with key a single identifier; anything else starting with '#' is a comment.
bool parse_metadata(std::string_view line, std::string& key, std::string& value) {
  std::string_view rest = trim(line.substr(1));
  std::size_t i = 0;
  while (i < rest.size() && (std::isalnum(static_cast<unsigned char>(rest[i])) || rest[i] == '_')) ++i;
  if (i == 0 || i >= rest.size()) return false;
  std::string_view after = rest.substr(i);
  if (after.front() != ':') return false;
  key = std::string(rest.substr(0, i));
  value = std::string(trim(after.substr(1)));
  return true;
}

bool is_triad_name(std::string_view name) {
  for (auto n : kTriadRates)
    if (n == name) return true;
  return false;
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

RecordingKind Recording::kind() const {
  for (const auto& n : names_)
    if (is_triad_name(n)) return RecordingKind::triad;
  return RecordingKind::single;
}

std::string Recording::row_location(std::size_t row) const {
  if (row < line_numbers_.size()) return str_cat(source_, ":", line_numbers_[row]);
  return str_cat(source_, " row ", row + 1);
}

std::vector<std::string> required_columns(RecordingKind kind, const Recording& recording) {
  std::vector<std::string> out;
  if (kind == RecordingKind::single) {
    for (auto n : kSingleRequired) out.emplace_back(n);
    return out;
  }
  out.emplace_back("t_s");
  for (auto n : kTriadRates) out.emplace_back(n);
  bool per_axis = false;
  for (auto n : kTriadTemps) per_axis = per_axis || recording.has(n);
  if (per_axis) {
    for (auto n : kTriadTemps) out.emplace_back(n);
  } else {
    out.emplace_back("temp_c");
  }
  return out;
}

namespace {

// The cells of one CSV line, trimmed.
void split_cells(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

// The rules of docs/recording_format.md a parsed table must meet: required columns present, finite values in
// them, t_s strictly increasing, integer position ids. Errors name the file, the line and the column.
void check_recording(const Recording& rec) {
  const RecordingKind kind = rec.kind();
  const std::vector<std::string> required = required_columns(kind, rec);
  for (const auto& name : required) {
    if (!rec.has(name)) {
      fail(rec.source(), ":", rec.header_line(), ": missing required column '", name, "' (a ", to_string(kind),
           "-gyro recording needs ", join(required), "; header has ", join(rec.names()), ")");
    }
  }
  for (const auto& name : required) {
    const auto& col = rec.column(name);
    for (std::size_t r = 0; r < col.size(); ++r) {
      if (!std::isfinite(col[r])) {
        fail(rec.row_location(r), ": column '", name, "': '", format_number(col[r]),
             "' in a required column (nan is allowed only in optional columns)");
      }
    }
  }
  const auto& t = rec.column("t_s");
  for (std::size_t r = 1; r < t.size(); ++r) {
    if (!(t[r] > t[r - 1])) {
      fail(rec.row_location(r), ": column 't_s': ", format_number(t[r]), " does not follow ", format_number(t[r - 1]),
           " (t_s must be strictly increasing)");
    }
  }
  if (rec.has("position_id")) {
    const auto& id = rec.column("position_id");
    for (std::size_t r = 0; r < id.size(); ++r) {
      if (!std::isnan(id[r]) && id[r] != std::round(id[r])) {
        fail(rec.row_location(r), ": column 'position_id': ", format_number(id[r]), " is not an integer");
      }
    }
  }
}

}  // namespace

void Recording::add_parsed_row(const std::vector<std::string_view>& cells, std::size_t line_no) {
  if (cells.size() != names_.size()) fail(source_, ":", line_no, ": row has ", cells.size(), " cells, the header has ", names_.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::string cell(cells[c]);
    char* end = nullptr;
    const double v = cell.empty() ? 0.0 : parse_c_double(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size()) {
      fail(source_, ":", line_no, ": column '", names_[c], "': cell '", cell, "' is not a number");
    }
    columns_[c].push_back(v);
  }
  line_numbers_.push_back(line_no);
}

void Recording::add_parsed_header(const std::vector<std::string_view>& cells, std::size_t line_no) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::string name(cells[c]);
    if (name.empty()) fail(source_, ":", line_no, ": header cell ", c + 1, " is empty");
    if (has(name)) fail(source_, ":", line_no, ": column '", name, "' appears twice in the header");
    names_.push_back(name);
    columns_.emplace_back();
  }
  header_line_ = line_no;
}

Recording parse_recording(std::string_view text, const std::string& source) {
  Recording rec(source);
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  std::size_t pos = 0, line_no = 0;
  bool have_header = false;
  std::vector<std::string_view> cells;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (trim(line).empty()) continue;
    if (line.front() == '#') {
      std::string key, value;
      if (!have_header && parse_metadata(line, key, value)) rec.set_meta(key, value);
      continue;
    }
    split_cells(line, cells);
    if (have_header) {
      rec.add_parsed_row(cells, line_no);
    } else {
      rec.add_parsed_header(cells, line_no);
      have_header = true;
    }
  }
  if (!have_header) fail(source, ": no header row (a recording needs a header and at least one row)");
  if (rec.rows() == 0) fail(source, ": header but no data rows");
  check_recording(rec);
  return rec;
}

Recording read_recording(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string(), ": cannot open recording");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_recording(buffer.str(), path.string());
}

std::string format_recording(const Recording& recording) {
  std::string out;
  out.reserve(recording.rows() * recording.names().size() * 12 + 256);
  out += "# format: ";
  out += kRecordingFormat;
  out += '\n';
  for (const auto& [key, value] : recording.metadata()) {
    if (key == "format") continue;
    out += "# " + key + ": " + value + "\n";
  }
  for (std::size_t c = 0; c < recording.names().size(); ++c) {
    if (c) out += ',';
    out += recording.names()[c];
  }
  out += '\n';
  std::vector<const std::vector<double>*> cols;
  for (const auto& name : recording.names()) cols.push_back(&recording.column(name));
  for (std::size_t r = 0; r < recording.rows(); ++r) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c) out += ',';
      out += format_number((*cols[c])[r]);
    }
    out += '\n';
  }
  return out;
}

void write_recording(const Recording& recording, const std::filesystem::path& path) {
  write_file_atomic(path, format_recording(recording));
}

double uniform_sample_interval(const Recording& recording, std::string_view purpose) {
  const auto& t = recording.column("t_s");
  if (t.size() < 2) fail(recording.source(), ": ", purpose, " needs at least two samples");
  const double dt = t[1] - t[0];
  for (std::size_t r = 2; r < t.size(); ++r) {
    const double step = t[r] - t[r - 1];
    if (std::abs(step - dt) > 1e-4 * dt) {
      fail(recording.row_location(r), ": ", purpose, " needs uniform sampling, but the step here is ",
           format_number(step), " s after steps of ", format_number(dt),
           " s (gyrosid does not resample silently; resample the recording first)");
    }
  }
  return (t.back() - t.front()) / static_cast<double>(t.size() - 1);
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
