#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>

#include "core/error.h"

namespace gyrosid {

std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         str_cat(".", target.filename().string(), ".tmp.", ::getpid(), ".", counter.fetch_add(1));
}

void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& writer) {
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

}  // namespace gyrosid
