#include "cli/resume.h"

#include <sstream>

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

}  // namespace gyrosid::cli
