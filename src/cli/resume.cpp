#include "cli/resume.h"

#include <filesystem>
#include <sstream>

#include "core/atomic_file.h"

namespace gyrosid::cli {

std::string run_fingerprint(const CLI::App& command, const std::vector<std::string>& files) {
  std::istringstream options(command.config_to_str(true, false));
  std::string text, line;
  while (std::getline(options, line)) {
    if (line.rfind("resume=", 0) == 0 || line.rfind("out=", 0) == 0) continue;
    text += line + "\n";
  }
  return digest(text + file_digests(files));
}

Checkpoint run_checkpoint(const std::string& out, const std::string& name, const std::string& fingerprint, bool resume) {
  if (resume) remove_stale_temporaries(out);
  return Checkpoint(std::filesystem::path(out) / ("." + name + "_checkpoint.json"), fingerprint, resume);
}

}  // namespace gyrosid::cli
