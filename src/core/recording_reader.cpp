#include "core/recording_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/blank_trim.h"
#include "core/error.h"
#include "core/format.h"

namespace gyrosid {
namespace {

// "# key: value" with key a single identifier; anything else starting with '#' is a comment.
bool parse_metadata(std::string_view line, std::string& key, std::string& value) {
  std::string_view rest = trim_blanks(line.substr(1));
  std::size_t i = 0;
  while (i < rest.size() && (std::isalnum(static_cast<unsigned char>(rest[i])) || rest[i] == '_')) ++i;
  if (i == 0 || i >= rest.size()) return false;
  std::string_view after = rest.substr(i);
  if (after.front() != ':') return false;
  key = std::string(rest.substr(0, i));
  value = std::string(trim_blanks(after.substr(1)));
  return true;
}

// The cells of one CSV line, trimmed.
void split_cells(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trim_blanks(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

// A cell as a number, or nullopt. std::from_chars reads the common forms (correctly rounded, as strtod);
// whatever it refuses or reads only in part - a leading '+', hexadecimal, out of range - goes to strtod in
// the C locale, the format's definition.
std::optional<double> parse_number(std::string_view cell) {
  if (cell.empty()) return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec == std::errc() && end == cell.data() + cell.size()) return v;
  const std::string copy(cell);
  char* stop = nullptr;
  v = parse_c_double(copy.c_str(), &stop);
  if (stop != copy.c_str() + copy.size()) return std::nullopt;
  return v;
}

bool blank(std::string_view line) { return trim_blanks(line).empty(); }

}  // namespace

RecordingReader::RecordingReader(const std::filesystem::path& path, std::size_t chunk_bytes) : source_(path.string()) {
  file_.reset(std::fopen(path.c_str(), "rb"));
  if (!file_) fail(source_, ": cannot open recording");
  std::error_code ec;
  total_bytes_ = static_cast<std::size_t>(std::filesystem::file_size(path, ec));
  if (ec) total_bytes_ = 0;
  buffer_.resize(std::max<std::size_t>(chunk_bytes, 64));
  data_ = buffer_.data();
  eof_ = false;
  read_header();
}

RecordingReader::RecordingReader(std::string_view text, std::string source) : source_(std::move(source)) {
  data_ = text.data(), size_ = text.size();
  read_header();
}

RecordingReader::~RecordingReader() = default;

std::optional<std::size_t> RecordingReader::find(std::string_view name) const {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return i;
  return std::nullopt;
}

// The next line without its '\n'; from a file, the unread rest is moved to the front of the buffer and the
// buffer refilled (grown when one line fills it).
bool RecordingReader::next_line(std::string_view& line) {
  while (true) {
    const char* start = data_ + pos_;
    const void* nl = pos_ < size_ ? std::memchr(start, '\n', size_ - pos_) : nullptr;
    if (nl) {
      const auto length = static_cast<std::size_t>(static_cast<const char*>(nl) - start);
      line = std::string_view(start, length);
      pos_ += length + 1;
      ++line_;
      return true;
    }
    if (eof_) {
      if (pos_ >= size_) return false;
      line = std::string_view(start, size_ - pos_);
      pos_ = size_;
      ++line_;
      return true;
    }
    const std::size_t rest = size_ - pos_;
    std::memmove(buffer_.data(), buffer_.data() + pos_, rest);
    consumed_ += pos_;
    pos_ = 0, size_ = rest;
    if (size_ == buffer_.size()) buffer_.resize(2 * buffer_.size());
    data_ = buffer_.data();
    const std::size_t got = std::fread(buffer_.data() + size_, 1, buffer_.size() - size_, file_.get());
    if (got == 0) {
      if (std::ferror(file_.get())) fail(source_, ": read error after ", consumed_ + size_, " bytes");
      eof_ = true;
    }
    size_ += got;
  }
}

void RecordingReader::read_header() {
  std::string_view line;
  while (next_line(line)) {
    if (line_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 byte-order mark
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (blank(line)) continue;
    if (line.front() == '#') {
      std::string key, value;
      if (parse_metadata(line, key, value)) {
        const auto it = std::find_if(metadata_.begin(), metadata_.end(), [&](const auto& kv) { return kv.first == key; });
        if (it != metadata_.end()) it->second = value;
        else metadata_.emplace_back(key, value);
      }
      continue;
    }
    split_cells(line, cells_);
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      const std::string name(cells_[c]);
      if (name.empty()) fail(source_, ":", line_, ": header cell ", c + 1, " is empty");
      if (find(name)) fail(source_, ":", line_, ": column '", name, "' appears twice in the header");
      names_.push_back(name);
    }
    header_line_ = line_;
    const RecordingKind k = kind();
    const std::vector<std::string> required = required_columns(k, names_);
    for (const auto& name : required) {
      if (!find(name)) {
        fail(source_, ":", header_line_, ": missing required column '", name, "' (a ", to_string(k), "-gyro recording needs ",
             join(required), "; header has ", join(names_), ")");
      }
      required_.push_back(*find(name));
    }
    t_column_ = find("t_s");
    position_column_ = find("position_id");
    return;
  }
  fail(source_, ": no header row (a recording needs a header and at least one row)");
}

void RecordingReader::parse_row(std::string_view line, std::vector<double>& row) {
  split_cells(line, cells_);
  if (cells_.size() != names_.size()) fail(source_, ":", line_, ": row has ", cells_.size(), " cells, the header has ", names_.size());
  row.resize(names_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const std::optional<double> v = parse_number(cells_[c]);
    if (!v) fail(source_, ":", line_, ": column '", names_[c], "': cell '", cells_[c], "' is not a number");
    row[c] = *v;
  }
}

// The rules of docs/recording_format.md on one row: finite values in the required columns, t_s strictly
// increasing, integer position ids.
void RecordingReader::check_row(const std::vector<double>& row) {
  for (std::size_t c : required_) {
    if (!std::isfinite(row[c])) {
      fail(source_, ":", line_, ": column '", names_[c], "': '", format_number(row[c]),
           "' in a required column (nan is allowed only in optional columns)");
    }
  }
  const double t = row[*t_column_];
  if (rows_ > 0 && !(t > last_t_)) {
    fail(source_, ":", line_, ": column 't_s': ", format_number(t), " does not follow ", format_number(last_t_), " (t_s must be strictly increasing)");
  }
  last_t_ = t;
  if (position_column_) {
    const double id = row[*position_column_];
    if (!std::isnan(id) && id != std::round(id)) fail(source_, ":", line_, ": column 'position_id': ", format_number(id), " is not an integer");
  }
}

bool RecordingReader::next(std::vector<double>& row) {
  std::string_view line;
  while (next_line(line)) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (blank(line) || line.front() == '#') continue;
    parse_row(line, row);
    check_row(row);
    ++rows_;
    return true;
  }
  if (rows_ == 0) fail(source_, ": header but no data rows");
  return false;
}

std::size_t count_recording_rows(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) fail(path.string(), ": cannot open recording");
  std::vector<char> buffer(RecordingReader::kChunkBytes);
  std::size_t lines = 0;    // data-like lines: the header and the rows
  bool at_start = true;     // before the current line's first character that is not a space or a tab
  char first = '\0';
  const auto end_line = [&] {
    if (first != '\0' && first != '#' && first != '\r') ++lines;
    at_start = true, first = '\0';
  };
  bool first_chunk = true;
  while (const std::size_t got = std::fread(buffer.data(), 1, buffer.size(), file.get())) {
    std::size_t i = first_chunk && got >= 3 && std::memcmp(buffer.data(), "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;  // byte-order mark
    first_chunk = false;
    while (i < got) {
      while (at_start && i < got && (buffer[i] == ' ' || buffer[i] == '\t')) ++i;
      if (i == got) break;
      if (at_start && buffer[i] != '\n') first = buffer[i], at_start = false;
      const void* nl = std::memchr(buffer.data() + i, '\n', got - i);
      if (!nl) break;
      i = static_cast<std::size_t>(static_cast<const char*>(nl) - buffer.data()) + 1;
      end_line();
    }
  }
  end_line();
  return lines > 0 ? lines - 1 : 0;  // less the header
}

}  // namespace gyrosid
