#include "core/ulog_format.h"

#include <bit>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace gyrosid::ulog {

static_assert(std::endian::native == std::endian::little, "the ULog reader copies little-endian values as they are");

namespace {

constexpr std::uint8_t kMagic[7] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35};  // "ULog" 01 12 35
constexpr std::size_t kFlagBitsSize = 40;  // compat[8], incompat[8], appended_offsets[3] (uint64)
constexpr std::size_t kMaxMessage = std::numeric_limits<std::uint16_t>::max();

// At most `n` characters of untrusted text, for messages.
std::string excerpt(std::string_view text, std::size_t n = 60) {
  std::string out(text.substr(0, n));
  for (char& c : out) c = (c < 32 || c > 126) ? '?' : c;
  return text.size() > n ? out + "..." : out;
}

}  // namespace

std::uint16_t read_u16(const std::uint8_t* p) {
  std::uint16_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

std::uint64_t read_u64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

MessageStream::MessageStream(std::istream& in, std::string source) : in_(in), source_(std::move(source)) {
  std::uint8_t header[kHeaderSize];
  std::size_t got = 0;
  stream_pos_ = 0;
  if (!read_at(0, header, sizeof header, got)) {
    fail(source_, ": not a ULog file (", got, " bytes; a ULog starts with a 16-byte header)");
  }
  if (std::memcmp(header, kMagic, sizeof kMagic) != 0) fail(source_, ": not a ULog file (its first bytes are not the ULog magic 'ULog' 01 12 35)");
  version_ = header[7];
  start_time_us_ = read_u64(header + 8);
  read_flag_bits();
  rewind();
}

void MessageStream::read_flag_bits() {
  std::uint8_t h[3];
  std::size_t got = 0;
  if (!read_at(kHeaderSize, h, 3, got) || h[2] != 'B') return;  // a version 1 log: no flag bits
  const std::uint16_t size = read_u16(h);
  std::uint8_t bits[kFlagBitsSize];
  if (size < kFlagBitsSize) fail(where(kHeaderSize), ": the flag bits message has ", size, " bytes, fewer than its ", kFlagBitsSize);
  if (!read_at(kHeaderSize + 3, bits, sizeof bits, got)) fail(where(kHeaderSize), ": the file ends inside the flag bits message");
  const std::uint8_t* incompat = bits + 8;
  bool unknown = (incompat[0] & ~1u) != 0;
  for (int i = 1; i < 8; ++i) unknown = unknown || incompat[i] != 0;
  if (unknown) fail(where(kHeaderSize), ": the log sets incompatible flag bits this reader does not know (a newer ULog); the format forbids reading it");
  if ((incompat[0] & 1u) == 0) return;
  const std::uint64_t data_start = kHeaderSize + 3 + size;
  for (int i = 0; i < 3; ++i) {
    const std::uint64_t offset = read_u64(bits + 16 + 8 * i);
    if (offset == 0) continue;
    if (offset < data_start || (!appended_.empty() && offset <= appended_.back())) {
      notes_.push_back(str_cat("appended-data offset ", offset, " ignored (before the data section or not increasing)"));
      continue;
    }
    appended_.push_back(offset);
  }
}

bool MessageStream::read_at(std::uint64_t offset, void* out, std::size_t n, std::size_t& got) {
  if (stream_pos_ != offset) {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    stream_pos_ = offset;
  }
  in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
  got = static_cast<std::size_t>(in_.gcount());
  stream_pos_ += got;
  if (got != n) stream_pos_ = std::numeric_limits<std::uint64_t>::max();  // unknown: seek before the next read
  return got == n;
}

void MessageStream::rewind() {
  pos_ = kHeaderSize;
  segment_ = 0;
  std::vector<std::string> kept;  // the flag bits' notes stay; the walk's start afresh
  for (const auto& n : notes_) {
    if (n.starts_with("appended-data offset")) kept.push_back(n);
  }
  notes_ = std::move(kept);
}

std::string MessageStream::where(std::uint64_t offset) const { return str_cat(source_, ": byte ", offset); }

bool MessageStream::next(Message& m) {
  while (true) {
    const bool bounded = segment_ < appended_.size();
    const std::uint64_t end = bounded ? appended_[segment_] : std::numeric_limits<std::uint64_t>::max();
    std::uint8_t h[3];
    std::size_t got = 0;
    const bool header_fits = !bounded || pos_ + 3 <= end;
    if (header_fits && !read_at(pos_, h, 3, got)) {
      if (got > 0) notes_.push_back(str_cat("the file ends inside a message header at byte ", pos_, ": its ", got, " byte(s) were discarded (truncated log)"));
      return false;
    }
    const std::uint64_t size = header_fits ? read_u16(h) : 0;
    if (!header_fits || pos_ + 3 + size > end) {  // cut where the appended data begin
      if (pos_ != end) notes_.push_back(str_cat("a message cut at byte ", pos_, " by the data appended at byte ", end, " was discarded"));
      pos_ = end;
      ++segment_;
      continue;
    }
    m.payload.resize(size);
    if (size > 0 && !read_at(pos_ + 3, m.payload.data(), size, got)) {
      notes_.push_back(str_cat("the file ends inside a '", excerpt(std::string(1, static_cast<char>(h[2]))), "' message at byte ", pos_, " (", got,
                               " of its ", size, " bytes): it was discarded (truncated log)"));
      return false;
    }
    m.type = static_cast<char>(h[2]);
    m.offset = pos_;
    pos_ += 3 + size;
    return true;
  }
}

Format parse_format(std::string_view text, const std::string& where) {
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0) fail(where, ": format '", excerpt(text), "' has no 'name:' before its fields");
  Format f;
  f.name = std::string(text.substr(0, colon));
  std::string_view rest = text.substr(colon + 1);
  while (!rest.empty()) {
    const std::size_t semi = rest.find(';');
    const std::string_view item = rest.substr(0, semi);
    rest = semi == std::string_view::npos ? std::string_view{} : rest.substr(semi + 1);
    if (item.empty()) continue;
    const std::size_t space = item.find(' ');
    if (space == std::string_view::npos || space == 0 || space + 1 == item.size()) {
      fail(where, ": format '", excerpt(f.name), "': field '", excerpt(item), "' is not 'type name'");
    }
    Field field;
    std::string_view type = item.substr(0, space);
    field.name = std::string(item.substr(space + 1));
    if (const std::size_t open = type.find('['); open != std::string_view::npos) {
      const std::string_view n = type.substr(open + 1, type.size() - open - 2);
      std::size_t count = 0;
      bool ok = type.back() == ']' && !n.empty() && n.size() <= 5;
      for (char c : n) ok = ok && c >= '0' && c <= '9', count = count * 10 + static_cast<std::size_t>(c - '0');
      if (!ok || count > kMaxMessage) fail(where, ": format '", excerpt(f.name), "': field '", excerpt(item), "' has a malformed array length");
      field.count = count;
      field.array = true;
      type = type.substr(0, open);
    }
    field.type = std::string(type);
    f.fields.push_back(std::move(field));
  }
  if (f.fields.empty()) fail(where, ": format '", excerpt(f.name), "' has no fields");
  return f;
}

std::size_t basic_size(std::string_view t) {
  if (t == "int8_t" || t == "uint8_t" || t == "bool" || t == "char") return 1;
  if (t == "int16_t" || t == "uint16_t") return 2;
  if (t == "int32_t" || t == "uint32_t" || t == "float") return 4;
  if (t == "int64_t" || t == "uint64_t" || t == "double") return 8;
  return 0;
}

namespace {
template <typename T>
double as_double(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return static_cast<double>(v);
}
}  // namespace

double read_basic(const std::uint8_t* p, std::string_view t) {
  if (t == "float") return as_double<float>(p);
  if (t == "double") return as_double<double>(p);
  if (t == "int8_t") return as_double<std::int8_t>(p);
  if (t == "uint8_t" || t == "bool" || t == "char") return as_double<std::uint8_t>(p);
  if (t == "int16_t") return as_double<std::int16_t>(p);
  if (t == "uint16_t") return as_double<std::uint16_t>(p);
  if (t == "int32_t") return as_double<std::int32_t>(p);
  if (t == "uint32_t") return as_double<std::uint32_t>(p);
  if (t == "int64_t") return as_double<std::int64_t>(p);
  if (t == "uint64_t") return as_double<std::uint64_t>(p);
  fail("ULog: '", excerpt(t), "' is not a basic type");
}

std::size_t Formats::size_of(const std::string& type, const std::string& where, std::set<std::string>& open) const {
  if (const std::size_t b = basic_size(type)) return b;
  if (const auto it = sizes_.find(type); it != sizes_.end()) return it->second;
  const auto f = formats_.find(type);
  if (f == formats_.end()) fail(where, ": type '", excerpt(type), "' is neither a basic type nor a defined format");
  if (!open.insert(type).second) fail(where, ": format '", excerpt(type), "' contains itself (a circular definition)");
  std::size_t size = 0;
  for (const auto& field : f->second.fields) {
    size += field.count * size_of(field.type, where, open);
    if (size > kMaxMessage) fail(where, ": format '", excerpt(type), "' is larger than a ULog message can hold (", kMaxMessage, " bytes)");
  }
  open.erase(type);
  sizes_[type] = size;
  return size;
}

std::optional<FieldLocation> Formats::locate(const std::string& format, const std::string& field, const std::string& where) const {
  const auto f = formats_.find(format);
  if (f == formats_.end()) fail(where, ": no format defines '", excerpt(format), "'");
  std::set<std::string> open{format};
  std::size_t offset = 0;
  for (const auto& x : f->second.fields) {
    const std::size_t size = size_of(x.type, where, open);
    if (x.name == field) return FieldLocation{offset, x.type, x.count};
    offset += x.count * size;
    if (offset > kMaxMessage) fail(where, ": format '", excerpt(format), "' is larger than a ULog message can hold (", kMaxMessage, " bytes)");
  }
  return std::nullopt;
}

}  // namespace gyrosid::ulog
