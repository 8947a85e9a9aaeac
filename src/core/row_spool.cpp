#include "core/row_spool.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/distributed.h"
#include "core/error.h"

namespace gyrosid {
namespace {

[[noreturn]] void fail_io(const std::filesystem::path& file, const char* what) {
  fail(file.empty() ? std::string("a temporary spool file") : file.string(), ": ", what, " failed (", std::strerror(errno), ")");
}

int anonymous_file() {
  std::string name = (std::filesystem::temp_directory_path() / "gyrosid_spool_XXXXXX").string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) fail_io(name, "creating");
  ::unlink(name.c_str());  // gone when closed
  return fd;
}

void write_all(int fd, const char* data, std::size_t bytes, off_t at, const std::filesystem::path& file) {
  while (bytes > 0) {
    const ssize_t n = ::pwrite(fd, data, bytes, at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail_io(file, "writing");
    data += n, bytes -= static_cast<std::size_t>(n), at += n;
  }
}

void read_all(int fd, char* data, std::size_t bytes, off_t at, const std::filesystem::path& file) {
  while (bytes > 0) {
    const ssize_t n = ::pread(fd, data, bytes, at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail_io(file, "reading");
    data += n, bytes -= static_cast<std::size_t>(n), at += n;
  }
}

}  // namespace

RowSpool::RowSpool(std::size_t width) : fd_(anonymous_file()), width_(width) {
  if (width == 0) fail("a spool's rows need at least one value");
}

RowSpool::RowSpool(std::size_t width, const std::filesystem::path& file, std::size_t resume_rows) : width_(width) {
  if (width == 0) fail("a spool's rows need at least one value");
  const auto kept = static_cast<off_t>(resume_rows * width * sizeof(double));
  int saved = -1;  // the path's rows, read by a process that does not write there
  if (resume_rows > 0) {
    saved = ::open(file.c_str(), is_output_process() ? O_RDWR : O_RDONLY);
    struct stat st {};
    if (saved < 0 || ::fstat(saved, &st) != 0 || st.st_size < kept) {
      if (saved >= 0) ::close(saved);
      fail(file.string(), ": the checkpoint's ", resume_rows, " rows are not all there; run without --resume to start afresh");
    }
  }
  if (is_output_process()) {
    file_ = file;
    fd_ = saved >= 0 ? saved : ::open(file.c_str(), O_RDWR | O_CREAT, 0644);
    if (fd_ < 0) fail_io(file, "opening");
    if (::ftruncate(fd_, kept) != 0) fail_io(file, "truncating");  // what a killed append left
    rows_ = resume_rows;
    return;
  }
  fd_ = anonymous_file();
  std::vector<double> row(width);
  for (std::size_t i = 0; i < resume_rows; ++i) {
    read_all(saved, reinterpret_cast<char*>(row.data()), width * sizeof(double), static_cast<off_t>(i * width * sizeof(double)), file);
    append(row);
  }
  if (saved >= 0) ::close(saved);
}

RowSpool::RowSpool(RowSpool&& other) noexcept : fd_(other.fd_), width_(other.width_), rows_(other.rows_), file_(std::move(other.file_)) {
  other.fd_ = -1;
}

RowSpool& RowSpool::operator=(RowSpool&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_, width_ = other.width_, rows_ = other.rows_, file_ = std::move(other.file_);
    other.fd_ = -1;
  }
  return *this;
}

RowSpool::~RowSpool() {
  if (fd_ >= 0) ::close(fd_);
}

void RowSpool::append(const std::vector<double>& values) {
  if (values.size() % width_ != 0) fail("a spool of rows of ", width_, " values given ", values.size());
  write_all(fd_, reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double),
            static_cast<off_t>(rows_ * width_ * sizeof(double)), file_);
  rows_ += values.size() / width_;
}

void RowSpool::read(std::size_t index, double* row) const {
  if (index >= rows_) fail("a spool of ", rows_, " rows asked for row ", index);
  read_all(fd_, reinterpret_cast<char*>(row), width_ * sizeof(double), static_cast<off_t>(index * width_ * sizeof(double)), file_);
}

}  // namespace gyrosid
