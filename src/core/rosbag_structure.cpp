#include "core/rosbag_structure.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace gyrosid {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint64_t kMaxBodyBytes = std::uint64_t{1} << 30;  // a header or a walked record (a chunk: 768 KiB by default)

std::uint64_t little_endian(std::string_view bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = bytes.size(); i-- > 0;) v = (v << 8) | static_cast<unsigned char>(bytes[i]);
  return v;
}

// One record's header fields by name, every length checked; `at` is the header's offset in the file.
std::map<std::string, std::string_view> header_fields(std::string_view header, const std::string& path, std::uint64_t at) {
  std::map<std::string, std::string_view> fields;
  std::size_t i = 0;
  while (i < header.size()) {
    if (header.size() - i < 4) fail(path, ": byte ", at + i, ": a header field's length is cut off (damaged bag)");
    const std::uint64_t n = little_endian(header.substr(i, 4));
    if (n > header.size() - i - 4) fail(path, ": byte ", at + i, ": a header field of ", n, " bytes overruns its header (damaged bag)");
    const std::string_view field = header.substr(i + 4, n);
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) fail(path, ": byte ", at + i, ": a header field without '=' (damaged bag)");
    fields[std::string(field.substr(0, eq))] = field.substr(eq + 1);
    i += 4 + n;
  }
  return fields;
}

std::optional<std::uint64_t> number_field(const std::map<std::string, std::string_view>& f, const std::string& name, std::size_t bytes) {
  const auto it = f.find(name);
  if (it == f.end() || it->second.size() != bytes) return std::nullopt;
  return little_endian(it->second);
}

struct Walk {
  const std::string& path;
  std::set<std::uint64_t> chunks;                         // file offsets of chunk records
  std::optional<std::uint64_t> index_pos;                 // from the bag header
  std::vector<std::uint64_t> chunk_positions;             // from chunk info records
  std::set<std::uint64_t> boundaries;                     // top-level record starts
  std::set<std::uint64_t> last_chunk_records;             // record starts in the last uncompressed chunk
  bool last_chunk_uncompressed = false;

  // The records of an uncompressed chunk's data (file offset `base`).
  void chunk_records(std::string_view data, std::uint64_t base);
  void record(const std::map<std::string, std::string_view>& f, std::string_view body, std::uint64_t at, std::uint64_t body_at, bool inner);
};

void Walk::chunk_records(std::string_view data, std::uint64_t base) {
  std::size_t i = 0;
  while (i < data.size()) {
    const std::uint64_t at = base + i;
    last_chunk_records.insert(i);
    if (data.size() - i < 4) fail(path, ": byte ", at, ": a record's header length is cut off (damaged bag)");
    const std::uint64_t h = little_endian(data.substr(i, 4));
    if (h > data.size() - i - 4) fail(path, ": byte ", at, ": a record header of ", h, " bytes overruns its chunk (damaged bag)");
    const auto fields = header_fields(data.substr(i + 4, h), path, at + 4);
    const std::size_t d = i + 4 + h;
    if (data.size() - d < 4) fail(path, ": byte ", base + d, ": a record's data length is cut off (damaged bag)");
    const std::uint64_t n = little_endian(data.substr(d, 4));
    if (n > data.size() - d - 4) fail(path, ": byte ", base + d, ": record data of ", n, " bytes overrun its chunk (damaged bag)");
    record(fields, data.substr(d + 4, n), at, base + d + 4, true);
    i = d + 4 + n;
  }
}

void Walk::record(const std::map<std::string, std::string_view>& f, std::string_view body, std::uint64_t at, std::uint64_t body_at, bool inner) {
  const auto op = f.find("op");
  if (op == f.end() || op->second.size() != 1) fail(path, ": byte ", at, ": a record without a one-byte op (damaged bag)");
  const auto code = static_cast<unsigned char>(op->second[0]);
  if (code == 0x07) header_fields(body, path, body_at);  // a connection's data is a header
  if (inner) return;
  if (code == 0x03) index_pos = number_field(f, "index_pos", 8);
  if (code == 0x06) {
    const auto pos = number_field(f, "chunk_pos", 8);
    if (!pos) fail(path, ": byte ", at, ": chunk info without an 8-byte chunk_pos (damaged bag)");
    chunk_positions.push_back(*pos);
  }
  if (code == 0x05) {
    chunks.insert(at);
    const auto compression = f.find("compression");
    last_chunk_uncompressed = compression != f.end() && compression->second == "none";
    last_chunk_records.clear();
    if (last_chunk_uncompressed) {
      if (number_field(f, "size", 4) != body.size()) fail(path, ": byte ", at, ": an uncompressed chunk's size is not its data's (damaged bag)");
      chunk_records(body, body_at);
    }
  }
  if (code == 0x04 && last_chunk_uncompressed) {
    const auto count = number_field(f, "count", 4);
    if (!count || body.size() != *count * 12) fail(path, ": byte ", at, ": index data whose count is not its size (damaged bag)");
    for (std::size_t k = 0; k < *count; ++k) {
      if (!last_chunk_records.count(little_endian(body.substr(k * 12 + 8, 4)))) {
        fail(path, ": byte ", body_at + k * 12, ": an index entry that points at no record of its chunk (damaged bag)");
      }
    }
  }
}

}  // namespace

void check_rosbag_structure(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, ": cannot open");
  in.seekg(0, std::ios::end);
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  std::string magic(kMagic.size(), '\0');
  if (!in.read(magic.data(), static_cast<std::streamsize>(magic.size())) || magic != kMagic) {
    fail(path, ": not a ROS 1 bag of format 2.0 (it must start with '#ROSBAG V2.0')");
  }
  // Top-level records one at a time (bounded memory): a header and the bodies that are walked are read, the
  // rest skipped.
  Walk w{path};
  std::string header, body;
  const auto read_length = [&](std::uint64_t at, const char* what) {
    char b[4];
    if (size - at < 4 || !in.read(b, 4)) fail(path, ": byte ", at, ": ", what, " is cut off (damaged bag)");
    return little_endian(std::string_view(b, 4));
  };
  for (std::uint64_t at = kMagic.size(); at < size;) {
    w.boundaries.insert(at);
    const std::uint64_t h = read_length(at, "a record's header length");
    if (h > size - at - 4 || h > kMaxBodyBytes) fail(path, ": byte ", at, ": a record header of ", h, " bytes overruns the file (damaged bag)");
    header.resize(h);
    in.read(header.data(), static_cast<std::streamsize>(h));
    const auto fields = header_fields(header, path, at + 4);
    const std::uint64_t d = at + 4 + h;
    const std::uint64_t n = read_length(d, "a record's data length");
    if (n > size - d - 4) fail(path, ": byte ", d, ": record data of ", n, " bytes overrun the file (damaged bag)");
    const auto op = fields.find("op");
    const bool walked = op != fields.end() && op->second.size() == 1 && (op->second[0] == 0x05 || op->second[0] == 0x04 || op->second[0] == 0x07);
    if (walked && n > kMaxBodyBytes) fail(path, ": byte ", d, ": a record of ", n, " bytes, beyond any bag's (damaged bag)");
    body.resize(walked ? n : 0);
    if (walked) in.read(body.data(), static_cast<std::streamsize>(n));
    else in.seekg(static_cast<std::streamoff>(n), std::ios::cur);
    w.record(fields, body, at, d + 4, false);
    at = d + 4 + n;
  }
  if (w.index_pos && *w.index_pos != 0 && !w.boundaries.count(*w.index_pos)) {
    fail(path, ": the bag header's index_pos ", *w.index_pos, " is no record's start (damaged bag)");
  }
  for (const std::uint64_t pos : w.chunk_positions) {
    if (!w.chunks.count(pos)) fail(path, ": chunk info points at byte ", pos, ", where no chunk starts (damaged bag)");
  }
}

}  // namespace gyrosid
