#include "core/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <atomic>
#include <fstream>

#include "core/distributed.h"
#include "core/error.h"

namespace gyrosid {

std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         str_cat(".", target.filename().string(), ".tmp.", ::getpid(), ".", counter.fetch_add(1));
}

void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& writer) {
  if (!is_output_process()) return;  // a distributed run writes its results once, from the first process
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) fail(path.string(), ": cannot create directory ", path.parent_path().string(), ": ", ec.message());
  }
  const std::filesystem::path tmp = temporary_sibling(path);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) fail(path.string(), ": cannot open for writing");
      writer(out);
      out.flush();
      if (!out) fail(path.string(), ": write failed (disk full?)");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) fail(path.string(), ": cannot move result into place: ", ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  write_file_atomic(path, [&](std::ostream& out) { out << content; });
}

int remove_stale_temporaries(const std::filesystem::path& dir) {
  int removed = 0;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const auto at = name.find(".tmp.");
    if (name.empty() || name[0] != '.' || at == std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::strtol(name.c_str() + at + 5, nullptr, 10));
    if (pid <= 0 || (::kill(pid, 0) != 0 && errno == ESRCH)) {
      std::filesystem::remove(entry.path(), ec);
      removed += ec ? 0 : 1;
    }
  }
  return removed;
}

}  // namespace gyrosid
