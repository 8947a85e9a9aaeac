#include "cli/resume.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/config.h"
#include "core/error.h"

namespace gyrosid::cli {

namespace {

// A file's fingerprint read 1 MB at a time: the digest of its chunks' digests (a 10^7-sample recording is a
// GB of text; holding it whole to digest it was the peak memory of explain). Built-in configs by their text.
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

std::string run_fingerprint(const CLI::App& command, const std::vector<std::string>& files) {
  std::istringstream options(command.config_to_str(true, false));
  std::string text, line;
  while (std::getline(options, line)) {
    if (line.rfind("resume=", 0) == 0 || line.rfind("out=", 0) == 0) continue;
    text += line + "\n";
  }
  for (const auto& f : files) {
    try {
      text += "|" + file_digest(f);
    } catch (const Error&) {
      text += "|" + f;
    }
  }
  return digest(text);
}

Checkpoint run_checkpoint(const std::string& out, const std::string& name, const std::string& fingerprint, bool resume) {
  if (resume) remove_stale_temporaries(out);
  return Checkpoint(std::filesystem::path(out) / ("." + name + "_checkpoint.json"), fingerprint, resume);
}

}  // namespace gyrosid::cli
