// A kill-safe record of a long computation's finished pieces (Monte Carlo runs, sweep points, bootstrap
// replicates), so that `--resume` continues where a killed run stopped and ends with the same bytes as an
// uninterrupted run. Pieces must be deterministic per index (seeded streams), so recomputing the missing ones
// gives what the uninterrupted run would have.
//
// The file is JSON, rewritten atomically at every save (a kill leaves the previous save intact). It holds a
// fingerprint of what is being computed - a resume with other inputs or options is refused - named series
// of doubles, stored exactly (shortest round-trip decimal), and named records (JSON objects, doubles exact too)
// for pieces with more structure, such as a finished stage of a search.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gyrosid {

class Checkpoint {
 public:
  Checkpoint() = default;  // disabled: saves nothing, resumes nothing
  // resume = false starts afresh; resume = true loads `file` if it exists (Error when its fingerprint differs).
  Checkpoint(std::filesystem::path file, std::string fingerprint, bool resume);

  bool enabled() const { return !file_.empty(); }
  const std::vector<double>& series(const std::string& name) const;  // empty when never saved
  void save(const std::string& name, std::vector<double> values);
  const nlohmann::json& record(const std::string& name) const;  // null when never saved
  void save_record(const std::string& name, nlohmann::json value);
  // The file beside the checkpoint where series `name`, too large to rewrite at every save, is appended
  // (core/row_spool.h); the checkpoint records how many of its rows are saved. Empty when disabled.
  std::filesystem::path spool_file(const std::string& name) const;
  // The computation completed and its results are written: the checkpoint and its spool files are removed.
  void finish();

 private:
  void write() const;
  std::filesystem::path file_;
  std::string fingerprint_;
  std::map<std::string, std::vector<double>> series_;
  std::map<std::string, nlohmann::json> records_;
};

// The checkpoint `<dir>/.<name>_checkpoint.json` of a resumable run writing into `dir`; on resume, the
// temporaries a killed write left in `dir` are removed first.
Checkpoint checkpoint_in(const std::filesystem::path& dir, const std::string& name, const std::string& fingerprint, bool resume);

// The numbers of a saved JSON array: JSON has no infinity or NaN, so a non-finite value is saved as null and
// read back as NaN (the summaries write both as null too).
std::vector<double> saved_numbers(const nlohmann::json& array);

// A short hex digest of text (FNV-1a 64), for fingerprints.
std::string digest(std::string_view text);

// The files' contents for a fingerprint: "|<digest>" per file, read 1 MB at a time (a 10^7-sample recording is
// a GB of text), a built-in config by its text; a name that is no readable file (a built-in flight) counts as
// itself.
std::string file_digests(const std::vector<std::string>& files);

}  // namespace gyrosid
