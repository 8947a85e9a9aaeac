// A recording read row by row, in fixed-size chunks of the file (docs/recording_format.md): memory holds one
// chunk and one row, whatever the file's length. Every row is checked as it is read - the number of cells,
// every cell a number (std::from_chars, with strtod in the C locale for the forms it does not take: a leading
// '+', hexadecimal), no nan in a required column, t_s strictly increasing, integer position ids - and an
// error names the file, the line and the column. read_recording (recording.h) builds a Recording on it;
// commands that need one column, or block means, or one chunk at a time read it directly.
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/recording.h"

namespace gyrosid {

class RecordingReader {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

  // Opens the file and reads its metadata and header; Error naming the file when it cannot be opened, has
  // no header, or its header lacks a required column.
  explicit RecordingReader(const std::filesystem::path& path, std::size_t chunk_bytes = kChunkBytes);
  // Reads text held in memory (not copied: it must outlive the reader).
  RecordingReader(std::string_view text, std::string source);
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  const std::string& source() const { return source_; }
  const std::vector<std::pair<std::string, std::string>>& metadata() const { return metadata_; }
  const std::vector<std::string>& names() const { return names_; }
  RecordingKind kind() const { return recording_kind(names_); }
  std::size_t header_line() const { return header_line_; }
  std::optional<std::size_t> find(std::string_view name) const;  // the column's index in a row

  // The next data row, one value per header column (nan where the file says so). False after the last row;
  // Error if the file had no data row at all.
  bool next(std::vector<double>& row);
  std::size_t line() const { return line_; }  // source line of the row last read
  std::size_t rows() const { return rows_; }  // rows read so far
  // Bytes consumed and the file's size (both 0 for text in memory), for progress.
  std::size_t bytes_read() const { return consumed_ + pos_; }
  std::size_t total_bytes() const { return total_bytes_; }

 private:
  bool next_line(std::string_view& line);
  void read_header();
  void parse_row(std::string_view line, std::vector<double>& row);
  void check_row(const std::vector<double>& row);

  std::string source_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_{nullptr, &std::fclose};
  std::vector<char> buffer_;
  const char* data_ = nullptr;  // unread bytes: data_[pos_, size_)
  std::size_t pos_ = 0, size_ = 0, consumed_ = 0, total_bytes_ = 0;
  bool eof_ = true;
  std::size_t line_ = 0, rows_ = 0, header_line_ = 0;
  std::vector<std::pair<std::string, std::string>> metadata_;
  std::vector<std::string> names_;
  std::vector<std::size_t> required_;  // column indices that may not hold nan
  std::optional<std::size_t> t_column_, position_column_;
  double last_t_ = 0.0;
  std::vector<std::string_view> cells_;
};

// Data rows of a recording file - its lines after the header that are neither blank nor comments - counted
// without parsing them (a pass over the file at the speed of reading it).
std::size_t count_recording_rows(const std::filesystem::path& path);

}  // namespace gyrosid
