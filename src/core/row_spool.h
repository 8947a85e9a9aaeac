// Fixed-width rows of doubles kept in a file, appended in index order and read back by index: the results of a
// long per-index computation held on disk instead of in memory (a lot's calibrated units, 10^4 and more), so
// that what follows reads them one at a time.
// The file is raw doubles in this machine's byte order: a private working file, not an exchange format.
// A spool at a path belongs to a checkpoint (core/checkpoint.h Checkpoint::spool_file): on resume its first
// `resume_rows` rows - those the checkpoint recorded after they were appended - are kept, and whatever a killed
// append left after them is cut off. Only the output process writes at the path (core/distributed.h); the
// other processes of `gyrosid-mpi` keep an anonymous copy of their own, started from the path's rows.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

namespace gyrosid {

class RowSpool {
 public:
  explicit RowSpool(std::size_t width);  // an anonymous temporary file, gone with the spool
  RowSpool(std::size_t width, const std::filesystem::path& file, std::size_t resume_rows);
  RowSpool(RowSpool&& other) noexcept;
  RowSpool& operator=(RowSpool&& other) noexcept;
  RowSpool(const RowSpool&) = delete;
  RowSpool& operator=(const RowSpool&) = delete;
  ~RowSpool();

  std::size_t width() const { return width_; }
  std::size_t rows() const { return rows_; }
  // Whole rows (values.size() a multiple of width), after the last.
  void append(const std::vector<double>& values);
  // Row `index` into row[0..width).
  void read(std::size_t index, double* row) const;

 private:
  int fd_ = -1;
  std::size_t width_ = 0, rows_ = 0;
  std::filesystem::path file_;  // empty when anonymous
};

}  // namespace gyrosid
