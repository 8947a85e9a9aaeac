#include "core/checkpoint.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "core/atomic_file.h"
#include "core/config.h"
#include "core/error.h"
#include "core/format.h"

namespace gyrosid {

std::string digest(std::string_view text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

namespace {

// A file's digest: the digest of its 1 MB chunks' digests (holding a recording whole to digest it was the
// peak memory of explain).
std::string file_digest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return digest(config_text(path));
  std::string chunk(1 << 20, '\0'), digests;
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    digests += digest(std::string_view(chunk.data(), static_cast<std::size_t>(in.gcount())));
  }
  return digest(digests);
}

}  // namespace

std::string file_digests(const std::vector<std::string>& files) {
  std::string text;
  for (const auto& f : files) {
    try {
      text += "|" + file_digest(f);
    } catch (const Error&) {
      text += "|" + f;
    }
  }
  return text;
}

Checkpoint::Checkpoint(std::filesystem::path file, std::string fingerprint, bool resume)
    : file_(std::move(file)), fingerprint_(std::move(fingerprint)) {
  if (!resume || !std::filesystem::exists(file_)) return;
  std::ifstream in(file_);
  nlohmann::json j;
  try {
    in >> j;
    if (j.at("fingerprint").get<std::string>() != fingerprint_) {
      fail(file_.string(), ": the checkpoint belongs to another computation (other inputs, options or seed); "
           "run without --resume to start afresh");
    }
    for (const auto& [name, values] : j.at("series").items()) series_[name] = values.get<std::vector<double>>();
    if (j.contains("records")) {
      for (const auto& [name, value] : j.at("records").items()) records_[name] = value;
    }
  } catch (const nlohmann::json::exception& e) {
    fail(file_.string(), ": unreadable checkpoint (", e.what(), "); run without --resume to start afresh");
  }
}

const std::vector<double>& Checkpoint::series(const std::string& name) const {
  static const std::vector<double> none;
  const auto it = series_.find(name);
  return it == series_.end() ? none : it->second;
}

void Checkpoint::save(const std::string& name, std::vector<double> values) {
  if (!enabled()) return;
  series_[name] = std::move(values);
  write();
}

const nlohmann::json& Checkpoint::record(const std::string& name) const {
  static const nlohmann::json none;
  const auto it = records_.find(name);
  return it == records_.end() ? none : it->second;
}

void Checkpoint::save_record(const std::string& name, nlohmann::json value) {
  if (!enabled()) return;
  records_[name] = std::move(value);
  write();
}

Checkpoint checkpoint_in(const std::filesystem::path& dir, const std::string& name, const std::string& fingerprint, bool resume) {
  if (resume) remove_stale_temporaries(dir);
  return Checkpoint(dir / ("." + name + "_checkpoint.json"), fingerprint, resume);
}

std::vector<double> saved_numbers(const nlohmann::json& array) {
  std::vector<double> out;
  for (const auto& v : array) out.push_back(v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN());
  return out;
}

// Streamed, not built as one JSON document: a lot's series hold every unit's numbers, and their document and
// its text were most of `lot learn`'s memory. The same JSON as the document's dump, numbers shortest
// round-trip, non-finite ones null.
void Checkpoint::write() const {
  write_file_atomic(file_, [&](std::ostream& out) {
    out << R"({"format":"gyrosid-checkpoint/1","fingerprint":)" << nlohmann::json(fingerprint_).dump() << R"(,"records":)"
        << nlohmann::json(records_).dump() << R"(,"series":{)";
    const char* between = "";
    for (const auto& [name, values] : series_) {
      out << between << nlohmann::json(name).dump() << ":[";
      for (std::size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << (std::isfinite(values[i]) ? format_number(values[i]) : "null");
      out << "]";
      between = ",";
    }
    out << "}}\n";
  });
}

std::filesystem::path Checkpoint::spool_file(const std::string& name) const {
  if (!enabled()) return {};
  return file_.parent_path() / (file_.stem().string() + "." + name + ".rows");
}

void Checkpoint::finish() {
  if (!enabled()) return;
  std::error_code ec;
  std::filesystem::remove(file_, ec);
  const std::string prefix = file_.stem().string() + ".";
  for (const auto& entry : std::filesystem::directory_iterator(file_.parent_path().empty() ? "." : file_.parent_path(), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && entry.path().extension() == ".rows") std::filesystem::remove(entry.path(), ec);
  }
}

}  // namespace gyrosid
