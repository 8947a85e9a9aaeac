// A ULog written from known values, for the reader's tests (PX4 docs, "ULog File Format"): the 16-byte header,
// then messages `uint16 size, uint8 type, payload`, little-endian. Only what the tests plant: no validation.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace gyrosid::testing_support {

// Little-endian payload bytes, field by field.
class Packer {
 public:
  template <typename T>
  Packer& put(T v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof v);
    return *this;
  }
  Packer& text(const std::string& s) {
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    return *this;
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

class UlogWriter {
 public:
  explicit UlogWriter(std::uint64_t start_us = 1000) {
    const std::uint8_t magic[8] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35, 0x01};
    bytes_.assign(magic, magic + 8);
    append(Packer().put(start_us).bytes());
  }
  // 'B': must come first. Returns the file offset of appended_offsets[0] (for patch_u64).
  std::size_t flag_bits(std::uint8_t incompat0 = 0, std::uint8_t incompat1 = 0) {
    Packer p;
    for (int i = 0; i < 8; ++i) p.put(std::uint8_t{0});
    p.put(incompat0).put(incompat1);
    for (int i = 2; i < 8; ++i) p.put(std::uint8_t{0});
    for (int i = 0; i < 3; ++i) p.put(std::uint64_t{0});
    message('B', p.bytes());
    return bytes_.size() - 24;
  }
  UlogWriter& format(const std::string& text) { return message('F', Packer().text(text).bytes()); }
  UlogWriter& info(const std::string& key, const std::string& value) {
    return message('I', Packer().put(static_cast<std::uint8_t>(key.size())).text(key).text(value).bytes());
  }
  UlogWriter& subscribe(std::uint8_t multi_id, std::uint16_t msg_id, const std::string& name) {
    return message('A', Packer().put(multi_id).put(msg_id).text(name).bytes());
  }
  UlogWriter& data(std::uint16_t msg_id, const Packer& fields) {
    Packer p;
    p.put(msg_id);
    std::vector<std::uint8_t> b = p.bytes();
    b.insert(b.end(), fields.bytes().begin(), fields.bytes().end());
    return message('D', b);
  }
  UlogWriter& dropout(std::uint16_t ms) { return message('O', Packer().put(ms).bytes()); }
  UlogWriter& sync() { return message('S', {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12}); }
  UlogWriter& logging(const std::string& text) {
    return message('L', Packer().put(std::uint8_t{'6'}).put(std::uint64_t{0}).text(text).bytes());
  }
  UlogWriter& message(char type, const std::vector<std::uint8_t>& payload) {
    append(Packer().put(static_cast<std::uint16_t>(payload.size())).put(static_cast<std::uint8_t>(type)).bytes());
    append(payload);
    return *this;
  }
  UlogWriter& raw(const std::vector<std::uint8_t>& b) {
    append(b);
    return *this;
  }
  void patch_u64(std::size_t offset, std::uint64_t v) { std::memcpy(bytes_.data() + offset, &v, sizeof v); }
  std::size_t size() const { return bytes_.size(); }
  std::string str() const { return std::string(bytes_.begin(), bytes_.end()); }

 private:
  void append(const std::vector<std::uint8_t>& b) { bytes_.insert(bytes_.end(), b.begin(), b.end()); }
  std::vector<std::uint8_t> bytes_;
};

}  // namespace gyrosid::testing_support
