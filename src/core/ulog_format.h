// The PX4 ULog container (PX4 docs, "ULog File Format"), read as a stream of messages in bounded memory.
//
// File: a 16-byte header (magic "ULog" 0x01 0x12 0x35, version byte, start time uint64 [us]), then messages,
// each `uint16 msg_size, uint8 msg_type, payload[msg_size]`, little-endian throughout. The definitions section
// (flag bits 'B' first, formats 'F', info 'I', multi-info 'M', parameters 'P', defaults 'Q') ends at the first
// subscription 'A' or logged string 'L'/'C'; the data section holds data 'D', strings, sync 'S', dropouts
// 'O' and more info and parameters. Unknown message types are skipped (the spec requires it); unknown
// incompatible flag bits are refused (the spec requires that too).
//
// Appended data (flag bits: incompat_flags[0] bit 0, up to three file offsets): the data section is read up to
// the first offset - a message that would cross it was cut when the data were appended, and is discarded - and
// continues at the offset, and so on for each. A file that ends inside a message (a log cut by power loss) ends
// there: the partial message is discarded and noted.
//
// A format `name:type field;type[n] field;...` may use another format as a type (nested, defined before or after
// its use, never circular); fields are packed without alignment, and a trailing `_padding` field may be left out
// of the data.
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace gyrosid::ulog {

struct Message {
  char type = 0;
  std::uint64_t offset = 0;            // of its 3-byte header, from the start of the file
  std::vector<std::uint8_t> payload;   // msg_size bytes
};

class MessageStream {
 public:
  // Reads and checks the header and the flag bits (Error naming the source for a file that is no ULog, or one
  // with incompatible flags this reader does not know).
  MessageStream(std::istream& in, std::string source);
  // The next message in file order; false at the end (or at a truncation, which is then noted).
  bool next(Message& m);
  // Back to the first message after the header; the notes start afresh.
  void rewind();

  std::uint64_t position() const { return pos_; }
  std::uint64_t start_time_us() const { return start_time_us_; }
  int version() const { return version_; }
  const std::vector<std::uint64_t>& appended_offsets() const { return appended_; }
  std::string where(std::uint64_t offset) const;
  // What the walk met: a truncated last message, messages cut at an appended-data offset.
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  void read_flag_bits();
  bool read_at(std::uint64_t offset, void* out, std::size_t n, std::size_t& got);

  std::istream& in_;
  std::string source_;
  int version_ = 0;
  std::uint64_t start_time_us_ = 0;
  std::vector<std::uint64_t> appended_;  // increasing, each past the header
  std::size_t segment_ = 0;              // messages are read up to appended_[segment_]
  std::uint64_t pos_ = 16;
  std::uint64_t stream_pos_ = 16;        // where the istream stands (reads are sequential but for jumps)
  std::vector<std::string> notes_;
};

inline constexpr std::uint64_t kHeaderSize = 16;

// Little-endian reads of the basic types.
std::uint16_t read_u16(const std::uint8_t* p);
std::uint64_t read_u64(const std::uint8_t* p);

struct Field {
  std::string type;        // a basic type or another format's name
  std::size_t count = 1;   // array length
  bool array = false;
  std::string name;
};

struct Format {
  std::string name;
  std::vector<Field> fields;
};

// "name:type field;type[n] field;" (Error naming `where` when malformed).
Format parse_format(std::string_view text, const std::string& where);

// Size in bytes of a basic type, 0 for any other name.
std::size_t basic_size(std::string_view type);
// A basic numeric value as a double (bool and char read as numbers).
double read_basic(const std::uint8_t* p, std::string_view type);

// Where a top-level field lies in a format's data.
struct FieldLocation {
  std::size_t offset = 0;
  std::string type;
  std::size_t count = 1;
};

class Formats {
 public:
  void add(Format f) {
    const std::string name = f.name;
    formats_[name] = std::move(f);
    sizes_.clear();  // a redefinition may change the sizes of the formats that use it
  }
  bool has(const std::string& name) const { return formats_.count(name) != 0; }
  // The top-level field `field` of `format`; nullopt when the format has no such field. Error (naming `where`)
  // for an undefined type, a circular definition or a format larger than a message.
  std::optional<FieldLocation> locate(const std::string& format, const std::string& field, const std::string& where) const;

 private:
  std::size_t size_of(const std::string& type, const std::string& where, std::set<std::string>& open) const;
  std::map<std::string, Format> formats_;
  mutable std::map<std::string, std::size_t> sizes_;
};

}  // namespace gyrosid::ulog
