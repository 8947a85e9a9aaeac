#include "core/imu_text_logs.h"

#include <array>
#include <charconv>
#include <limits>
#include <vector>

#include "core/blank_trim.h"
#include "core/error.h"
#include "core/format.h"
#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {

namespace {

std::optional<double> parse_double(std::string_view cell) {
  cell = trim_blanks(cell);
  if (cell.size() > 1 && cell.front() == '+' && cell[1] != '-') cell.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (cell.empty() || ec != std::errc() || end != cell.data() + cell.size()) return std::nullopt;
  return v;
}

std::optional<std::int64_t> parse_int64(std::string_view cell) {
  cell = trim_blanks(cell);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (cell.empty() || ec != std::errc() || end != cell.data() + cell.size()) return std::nullopt;
  return v;
}

// The lines of a text log, one at a time, counted (for messages) and measured in bytes (for progress).
class LineSource {
 public:
  LineSource(std::istream& in, std::string source) : in_(in), source_(std::move(source)) {}
  // The next line that is not blank, without its line end; false at the end.
  bool next(std::string_view& line) {
    while (std::getline(in_, buffer_)) {
      ++line_no_;
      bytes_ += buffer_.size() + 1;
      line = trim_blanks(buffer_);
      if (!line.empty()) return true;
    }
    return false;
  }
  std::size_t line_no() const { return line_no_; }
  std::uint64_t bytes() const { return bytes_; }
  const std::string& source() const { return source_; }
  std::string where(std::uint64_t line) const { return str_cat(source_, ":", line); }

 private:
  std::istream& in_;
  std::string source_;
  std::string buffer_;
  std::size_t line_no_ = 0;
  std::uint64_t bytes_ = 0;
};

void split(std::string_view line, char delimiter, std::vector<std::string_view>& cells) {
  cells.clear();
  if (delimiter != ' ') {
    for (std::size_t start = 0;;) {
      const std::size_t at = line.find(delimiter, start);
      cells.push_back(trim_blanks(line.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start)));
      if (at == std::string_view::npos) return;
      start = at + 1;
    }
  }
  for (std::size_t i = 0; i < line.size();) {  // runs of blanks separate
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) cells.push_back(line.substr(start, i - start));
  }
}

// One quantity a CSV log must (or may) give: the names it goes by in the dialect's header, and the units
// ("" for none written) it may carry in brackets.
struct ColumnRole {
  std::string what;  // "gyro x", for messages
  std::vector<std::string> names;
  std::vector<std::string> units;
};

std::vector<ColumnRole> roles(CsvImuDialect d) {
  std::vector<ColumnRole> r;
  const bool ros = d == CsvImuDialect::ros;
  r.push_back({"time", {ros ? "%time" : "timestamp"}, {"", "ns"}});
  for (const char* a : kTriadAxes) {
    r.push_back({str_cat("gyro ", a), ros ? std::vector<std::string>{str_cat("field.angular_velocity.", a)}
                                          : std::vector<std::string>{str_cat("omega_", a), str_cat("w_RS_S_", a)},
                 {"", "rad s^-1", "rad/s"}});
  }
  for (const char* a : kTriadAxes) {
    r.push_back({str_cat("accel ", a), ros ? std::vector<std::string>{str_cat("field.linear_acceleration.", a)}
                                           : std::vector<std::string>{str_cat("alpha_", a), str_cat("a_RS_S_", a)},
                 {"", "m s^-2", "m/s^2"}});
  }
  return r;
}

// "w_RS_S_x [rad s^-1]" -> name "w_RS_S_x", unit "rad s^-1".
std::pair<std::string, std::string> name_and_unit(std::string_view cell) {
  cell = trim_blanks(cell);
  const std::size_t open = cell.find('[');
  if (open == std::string_view::npos || cell.back() != ']') return {std::string(cell), ""};
  return {std::string(trim_blanks(cell.substr(0, open))), std::string(trim_blanks(cell.substr(open + 1, cell.size() - open - 2)))};
}

class CsvImuReader : public ImuLogReader {
 public:
  CsvImuReader(std::istream& in, std::string source, CsvImuDialect dialect) : lines_(in, std::move(source)) {
    read_header(dialect);
  }
  bool next(ImuLogSample& s) override;
  std::string where(std::uint64_t line) const override { return lines_.where(line); }
  std::uint64_t position() const override { return lines_.bytes(); }

 private:
  void read_header(CsvImuDialect dialect);
  std::size_t find_role(const ColumnRole& role, std::size_t header_line) const;
  double number(std::size_t column) const;

  LineSource lines_;
  std::vector<std::string> header_;       // the cells as written
  std::vector<std::string> names_;        // without units
  std::vector<std::string> units_;
  std::size_t time_ = 0;
  std::array<std::size_t, 3> gyro_{}, accel_{};
  std::vector<std::string_view> cells_;
};

std::size_t CsvImuReader::find_role(const ColumnRole& role, std::size_t header_line) const {
  std::size_t found = std::string::npos;
  for (std::size_t c = 0; c < names_.size(); ++c) {
    bool match = false;
    for (const auto& n : role.names) match = match || names_[c] == n;
    if (!match) continue;
    if (found != std::string::npos) fail(lines_.where(header_line), ": columns '", header_[found], "' and '", header_[c], "' both give the ", role.what);
    bool unit_ok = false;
    for (const auto& u : role.units) unit_ok = unit_ok || units_[c] == u;
    if (!unit_ok) fail(lines_.where(header_line), ": column '", header_[c], "': the ", role.what, " must be in ", role.units.back(), ", not '", units_[c], "'");
    found = c;
  }
  return found;
}

void CsvImuReader::read_header(CsvImuDialect dialect) {
  std::string_view line;
  // The header is the first line that is not blank; EuRoC's starts with '#'. A '#' line without a comma before
  // it is a comment.
  bool found = false;
  while ((found = lines_.next(line)) && line.front() == '#' && line.find(',') == std::string_view::npos) {
  }
  if (!found) fail(lines_.source(), ": no header row (an empty log)");
  const std::size_t header_line = lines_.line_no();
  if (line.front() == '#') line.remove_prefix(1);
  split(line, ',', cells_);
  for (auto cell : cells_) {
    header_.emplace_back(trim_blanks(cell));
    auto [name, unit] = name_and_unit(cell);
    names_.push_back(std::move(name));
    units_.push_back(std::move(unit));
  }
  const std::vector<ColumnRole> r = roles(dialect);
  std::array<std::size_t, 7> at{};
  for (std::size_t k = 0; k < r.size(); ++k) {
    at[k] = find_role(r[k], header_line);
    const bool accel = k >= 4;
    if (at[k] == std::string::npos && (!accel || find_role(r[4], header_line) != std::string::npos ||
                                       find_role(r[5], header_line) != std::string::npos || find_role(r[6], header_line) != std::string::npos)) {
      fail(lines_.where(header_line), ": no column for the ", r[k].what, ": '", join(r[k].names, "' or '"), "' (",
           accel ? "the accelerometer's columns come three or none; " : "", "the header has ", join(header_), ")");
    }
  }
  time_ = at[0];
  for (std::size_t k = 0; k < 3; ++k) gyro_[k] = at[1 + k], accel_[k] = at[4 + k];
  info_.ticks_per_second = 1'000'000'000;
  info_.time_source = names_[time_] + " [ns]";
  info_.has_accel = accel_[0] != std::string::npos;
}

double CsvImuReader::number(std::size_t column) const {
  const auto v = parse_double(cells_[column]);
  if (!v) fail(lines_.where(lines_.line_no()), ": column '", header_[column], "': '", cells_[column], "' is not a number");
  return *v;
}

bool CsvImuReader::next(ImuLogSample& s) {
  std::string_view line;
  do {
    if (!lines_.next(line)) return false;
  } while (line.front() == '#');
  split(line, ',', cells_);
  if (cells_.size() != header_.size()) {
    fail(lines_.where(lines_.line_no()), ": row has ", cells_.size(), " cells, the header has ", header_.size());
  }
  const auto stamp = parse_int64(cells_[time_]);
  if (!stamp) fail(lines_.where(lines_.line_no()), ": column '", header_[time_], "': '", cells_[time_], "' is not an integer time stamp in nanoseconds");
  s.stamp = *stamp;
  s.location = lines_.line_no();
  for (std::size_t k = 0; k < 3; ++k) {
    s.gyro_radps[k] = number(gyro_[k]);
    s.accel_mps2[k] = info_.has_accel ? number(accel_[k]) : NAN;
  }
  return true;
}

class ImuTkReader : public ImuLogReader {
 public:
  ImuTkReader(std::istream& gyro, std::string gyro_source, std::istream* accel, std::string accel_source, const ImuTkScaling& scaling)
      : gyro_(gyro, std::move(gyro_source)), scaling_(scaling) {
    if (accel) accel_.emplace(*accel, std::move(accel_source));
    info_.ticks_per_second = 1'000'000'000;
    info_.time_source = "t [s] (decimal seconds, to the nanosecond)";
    info_.has_accel = accel != nullptr;
  }
  bool next(ImuLogSample& s) override;
  std::string where(std::uint64_t line) const override { return gyro_.where(line); }
  std::uint64_t position() const override { return gyro_.bytes(); }

 private:
  // The next row "t x y z" of `lines`: its time stamp in ns and its three counts; false at the end.
  bool row(LineSource& lines, std::int64_t& ns, std::array<double, 3>& counts);
  LineSource gyro_;
  std::optional<LineSource> accel_;
  ImuTkScaling scaling_;
  std::vector<std::string_view> cells_;
};

bool ImuTkReader::row(LineSource& lines, std::int64_t& ns, std::array<double, 3>& counts) {
  std::string_view line;
  do {
    if (!lines.next(line)) return false;
  } while (line.front() == '#' || line.front() == '%');
  split(line, ' ', cells_);
  const std::string here = lines.where(lines.line_no());
  if (cells_.size() != 4) fail(here, ": row has ", cells_.size(), " values, expected 4 (t x y z)");
  const auto t = decimal_seconds_to_ns(cells_[0]);
  if (!t) fail(here, ": column 1 (t): '", cells_[0], "' is not a time in seconds");
  ns = *t;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto v = parse_double(cells_[k + 1]);
    if (!v) fail(here, ": column ", k + 2, " (", kTriadAxes[k], "): '", cells_[k + 1], "' is not a number");
    counts[k] = *v;
  }
  return true;
}

bool ImuTkReader::next(ImuLogSample& s) {
  std::array<double, 3> counts{};
  const bool more = row(gyro_, s.stamp, counts);
  s.location = gyro_.line_no();
  for (std::size_t k = 0; k < 3; ++k) s.gyro_radps[k] = units::dps_to_radps((counts[k] - scaling_.gyro_offset_counts) * scaling_.gyro_scale_dps_per_count);
  if (!accel_) return more;
  std::int64_t accel_stamp = 0;
  const bool accel_more = row(*accel_, accel_stamp, counts);
  if (more != accel_more) {
    fail(accel_->where(accel_->line_no()), ": the accelerometer log has ", accel_more ? "more" : "fewer", " rows than the gyro log ", gyro_.source());
  }
  if (!more) return false;
  if (accel_stamp != s.stamp) {
    fail(accel_->where(accel_->line_no()), ": time ", format_number(static_cast<double>(accel_stamp) * 1e-9), " s differs from the gyro log's ",
         format_number(static_cast<double>(s.stamp) * 1e-9), " s (", gyro_.where(gyro_.line_no()), ")");
  }
  for (std::size_t k = 0; k < 3; ++k) s.accel_mps2[k] = (counts[k] - scaling_.accel_offset_counts) * scaling_.accel_scale_mps2_per_count;
  return true;
}

}  // namespace

std::optional<std::int64_t> decimal_seconds_to_ns(std::string_view text) {
  text = trim_blanks(text);
  bool negative = false;
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) negative = text.front() == '-', text.remove_prefix(1);
  std::uint64_t mantissa = 0;
  int scale = 0;  // value = mantissa * 10^scale seconds
  bool digits = false, point = false;
  std::size_t i = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (c < '0' || c > '9') break;
    digits = true;
    if (mantissa < 100'000'000'000'000'000ULL) {
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(c - '0');
      scale -= point ? 1 : 0;
    } else if (!point) {
      ++scale;  // a digit beyond 18 significant ones, before the point: dropped, magnitude kept
    }
  }
  if (!digits) return std::nullopt;
  if (i < text.size()) {
    if (text[i] != 'e' && text[i] != 'E') return std::nullopt;
    int exponent = 0;
    const char* b = text.data() + i + 1;
    if (b < text.data() + text.size() && *b == '+') ++b;
    const auto [end, ec] = std::from_chars(b, text.data() + text.size(), exponent);
    if (ec != std::errc() || end != text.data() + text.size() || exponent > 400 || exponent < -400) return std::nullopt;
    scale += exponent;
  }
  scale += 9;  // to nanoseconds
  std::uint64_t ns = mantissa;
  if (scale >= 0) {
    for (int k = 0; k < scale; ++k) {
      if (ns > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) / 10) return std::nullopt;
      ns *= 10;
    }
  } else {
    if (scale < -19) return 0;
    std::uint64_t p = 1;
    for (int k = 0; k < -scale; ++k) p *= 10;
    ns = mantissa / p + (mantissa % p >= p - mantissa % p ? 1 : 0);  // half away from zero
  }
  if (ns > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
  const auto v = static_cast<std::int64_t>(ns);
  return negative ? -v : v;
}

std::unique_ptr<ImuLogReader> open_csv_imu_log(std::istream& in, std::string source, CsvImuDialect dialect) {
  return std::make_unique<CsvImuReader>(in, std::move(source), dialect);
}

std::unique_ptr<ImuLogReader> open_imu_tk_log(std::istream& gyro, std::string gyro_source, std::istream* accel, std::string accel_source,
                                              const ImuTkScaling& scaling) {
  return std::make_unique<ImuTkReader>(gyro, std::move(gyro_source), accel, std::move(accel_source), scaling);
}

}  // namespace gyrosid
