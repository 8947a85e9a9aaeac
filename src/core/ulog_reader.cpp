#include "core/ulog_reader.h"

#include <array>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/format.h"
#include "core/ulog_format.h"

namespace gyrosid {

namespace {

struct Subscription {
  std::string name;
  int multi_id = 0;
  std::uint64_t data = 0;  // data messages in the log
};

// Where one topic's fields lie in its data messages (after the 2-byte msg_id).
struct Decoder {
  ulog::FieldLocation time;
  std::array<ulog::FieldLocation, 3> gyro;
  std::optional<ulog::FieldLocation> temperature;
  std::size_t min_size = 0;  // bytes the fields need
};

// "char[5] ver_hw" -> "ver_hw"
std::string_view info_name(std::string_view key) {
  const std::size_t space = key.rfind(' ');
  return space == std::string_view::npos ? key : key.substr(space + 1);
}

// Text from the log for the recording's metadata: printable ASCII only, at most 80 characters.
std::string printable(std::string_view text) {
  std::string out;
  for (char c : text.substr(0, 80)) {
    if (c == 0) break;
    out += (c >= 32 && c < 127) ? c : ' ';
  }
  return out;
}

class UlogGyroReader : public ImuLogReader {
 public:
  UlogGyroReader(std::istream& in, std::string source, UlogGyroChoice choice)
      : stream_(in, source), source_(std::move(source)), choice_(std::move(choice)), wanted_(65536, false) {
    while (stream_.next(message_)) scan(message_);
    make_decoder(choose_topic());
    stream_.rewind();
  }
  bool next(ImuLogSample& s) override;
  std::string where(std::uint64_t offset) const override { return stream_.where(offset); }
  std::uint64_t position() const override { return stream_.position(); }
  std::vector<ImuLogNote> notes() const override;

 private:
  void scan(const ulog::Message& m);
  bool has_data(const std::string& topic, int instance) const;
  std::string with_data(const std::string& topic) const;  // "sensor_gyro: instances 0, 1" or the topics with data
  std::string choose_topic() const;
  void make_decoder(const std::string& topic);
  ulog::FieldLocation field(const std::string& name, bool floating, std::size_t count = 1) const;

  ulog::MessageStream stream_;
  std::string source_;
  UlogGyroChoice choice_;
  ulog::Formats formats_;
  std::map<std::uint16_t, Subscription> subscriptions_;
  std::vector<bool> wanted_;  // by msg_id
  std::string topic_;
  Decoder decoder_;
  std::uint64_t dropouts_ = 0, dropout_ms_ = 0, unknown_ = 0, malformed_ = 0, orphans_ = 0;
  std::string sys_name_, ver_hw_;
  ulog::Message message_;
};

void UlogGyroReader::scan(const ulog::Message& m) {
  const auto& p = m.payload;
  const auto text = [&](std::size_t from) { return std::string_view(reinterpret_cast<const char*>(p.data()) + from, p.size() - from); };
  switch (m.type) {
    case 'F':
      try {  // a malformed format matters only if the chosen topic needs it: then "no format defines ..." says so
        formats_.add(ulog::parse_format(text(0), stream_.where(m.offset)));
        return;
      } catch (const Error&) {
        break;
      }
    case 'I': {
      if (p.empty() || p[0] > p.size() - 1) break;
      const std::string_view key = text(1).substr(0, p[0]);
      if (info_name(key) == "sys_name") sys_name_ = printable(text(1u + p[0]));
      if (info_name(key) == "ver_hw") ver_hw_ = printable(text(1u + p[0]));
      return;
    }
    case 'A':
      if (p.size() < 3) break;
      subscriptions_[ulog::read_u16(p.data() + 1)] = {std::string(text(3)), p[0], 0};
      return;
    case 'D': {
      if (p.size() < 2) break;
      const auto it = subscriptions_.find(ulog::read_u16(p.data()));
      if (it == subscriptions_.end()) ++orphans_;
      else ++it->second.data;
      return;
    }
    case 'O':
      if (p.size() < 2) break;
      ++dropouts_;
      dropout_ms_ += ulog::read_u16(p.data());
      return;
    case 'B': case 'M': case 'P': case 'Q': case 'L': case 'C': case 'S': case 'R':
      return;
    default:
      ++unknown_;
      return;
  }
  ++malformed_;  // too short for its type, or a format that does not parse
}

bool UlogGyroReader::has_data(const std::string& topic, int instance) const {
  for (const auto& [id, s] : subscriptions_) {
    if (s.name == topic && s.multi_id == instance && s.data > 0) return true;
  }
  return false;
}

std::string UlogGyroReader::with_data(const std::string& topic) const {
  std::vector<std::string> instances, topics;
  for (const auto& [id, s] : subscriptions_) {
    if (s.data == 0) continue;
    if (s.name == topic) instances.push_back(std::to_string(s.multi_id));
    const std::string name = str_cat(printable(s.name), s.multi_id ? str_cat(" (instance ", s.multi_id, ")") : "");
    if (topics.size() < 40) topics.push_back(name);
  }
  if (!instances.empty()) return str_cat("it has ", topic, " data for instance(s) ", join(instances), " (--instance)");
  return topics.empty() ? "it holds no data messages at all" : str_cat("topics with data: ", join(topics));
}

std::string UlogGyroReader::choose_topic() const {
  const int k = choice_.instance;
  if (!choice_.topic.empty()) {
    if (has_data(choice_.topic, k)) return choice_.topic;
    fail(source_, ": no ", choice_.topic, " data for instance ", k, "; ", with_data(choice_.topic));
  }
  if (has_data("sensor_gyro", k)) return "sensor_gyro";
  if (has_data("sensor_combined", k)) return "sensor_combined";
  fail(source_, ": no sensor_gyro or sensor_combined data for instance ", k, "; ", with_data("sensor_gyro"));
}

// A scalar (or array of `count`) field of the chosen topic: floating point (gyro, temperature) or a 64-bit
// integer (time).
ulog::FieldLocation UlogGyroReader::field(const std::string& name, bool floating, std::size_t count) const {
  const std::string where = str_cat(source_, " (format ", topic_, ")");
  const auto f = formats_.locate(topic_, name, where);
  if (!f) fail(where, ": no field '", name, "'");
  const bool type_ok = floating ? (f->type == "float" || f->type == "double") : (f->type == "uint64_t" || f->type == "int64_t");
  if (!type_ok || f->count < count) {
    fail(where, ": field '", name, "' is ", f->type, count > 1 ? str_cat("[", f->count, "]") : "", ", expected ",
         floating ? "float or double" : "a 64-bit integer", count > 1 ? str_cat("[", count, "]") : "");
  }
  return *f;
}

void UlogGyroReader::make_decoder(const std::string& topic) {
  topic_ = topic;
  const std::string where = str_cat(source_, " (format ", topic_, ")");
  const bool gyro = topic == "sensor_gyro";
  const std::string time = gyro && formats_.locate(topic, "timestamp_sample", where) ? "timestamp_sample" : "timestamp";
  decoder_.time = field(time, false);
  for (std::size_t k = 0; k < 3; ++k) {
    if (gyro) {
      decoder_.gyro[k] = field(std::string(1, static_cast<char>('x' + k)), true);
    } else {
      decoder_.gyro[k] = field("gyro_rad", true, 3);
      decoder_.gyro[k].offset += k * ulog::basic_size(decoder_.gyro[k].type);
    }
  }
  if (gyro && formats_.locate(topic, "temperature", where)) decoder_.temperature = field("temperature", true);
  const auto end = [](const ulog::FieldLocation& f) { return f.offset + ulog::basic_size(f.type); };
  decoder_.min_size = end(decoder_.time);
  for (const auto& g : decoder_.gyro) decoder_.min_size = std::max(decoder_.min_size, end(g));
  if (decoder_.temperature) decoder_.min_size = std::max(decoder_.min_size, end(*decoder_.temperature));
  for (const auto& [id, s] : subscriptions_) wanted_[id] = s.name == topic && s.multi_id == choice_.instance;
  info_.ticks_per_second = 1'000'000;
  info_.time_source = str_cat(topic, ".", time, " [us]");
  info_.has_temperature = decoder_.temperature.has_value();
  info_.temperature_source = info_.has_temperature ? topic + ".temperature" : "";
  std::vector<std::string> sensor;
  if (!sys_name_.empty()) sensor.push_back(sys_name_);
  if (!ver_hw_.empty()) sensor.push_back("board " + ver_hw_);
  sensor.push_back(str_cat(topic, " instance ", choice_.instance));
  info_.sensor = join(sensor);
}

bool UlogGyroReader::next(ImuLogSample& s) {
  while (stream_.next(message_)) {
    const auto& p = message_.payload;
    if (message_.type != 'D' || p.size() < 2 || !wanted_[ulog::read_u16(p.data())]) continue;
    const std::uint8_t* data = p.data() + 2;
    if (p.size() - 2 < decoder_.min_size) {
      fail(stream_.where(message_.offset), ": a ", topic_, " message of ", p.size() - 2, " bytes is shorter than its fields need (", decoder_.min_size, ")");
    }
    std::uint64_t stamp = ulog::read_u64(data + decoder_.time.offset);
    if (stamp > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      fail(stream_.where(message_.offset), ": ", info_.time_source, " ", stamp, " is out of range");
    }
    s.stamp = static_cast<std::int64_t>(stamp);
    for (std::size_t k = 0; k < 3; ++k) s.gyro_radps[k] = ulog::read_basic(data + decoder_.gyro[k].offset, decoder_.gyro[k].type);
    s.temp_c = decoder_.temperature ? ulog::read_basic(data + decoder_.temperature->offset, decoder_.temperature->type) : NAN;
    s.location = message_.offset;
    return true;
  }
  return false;
}

std::vector<ImuLogNote> UlogGyroReader::notes() const {
  std::vector<ImuLogNote> out;
  if (!stream_.notes().empty()) out.push_back({"log_damage", join(stream_.notes(), "; "), true});
  if (dropouts_ > 0) {
    out.push_back({"dropouts", str_cat(dropouts_, " in the log (", dropout_ms_, " ms in all): the logger lost messages there; the samples around them are kept and the gaps show in the time steps"), true});
  }
  if (malformed_ + orphans_ > 0) {
    out.push_back({"skipped_messages", str_cat(malformed_, " malformed (too short for their type, or a format that does not parse) and ", orphans_,
                                               " data messages of no subscription (a damaged log?)"), true});
  }
  if (!stream_.appended_offsets().empty()) {
    std::vector<std::string> at;
    for (auto o : stream_.appended_offsets()) at.push_back(std::to_string(o));
    out.push_back({"appended_data", str_cat("at byte(s) ", join(at), ", read as part of the data section"), false});
  }
  if (unknown_ > 0) out.push_back({"unknown_messages", str_cat(unknown_, " of types this reader does not know, skipped (as the ULog format requires)"), false});
  return out;
}

}  // namespace

std::unique_ptr<ImuLogReader> open_ulog_gyro(std::istream& in, std::string source, const UlogGyroChoice& choice) {
  return std::make_unique<UlogGyroReader>(in, std::move(source), choice);
}

}  // namespace gyrosid
