// Results are written atomically: to a temporary file beside the target, then renamed over it, so a run
// that fails (or is killed) never leaves a half-written result behind.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace gyrosid {

// Creates missing parent directories, writes through `writer`, checks the stream, renames into place. In a
// distributed run (core/distributed.h) only the first process writes.
void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& writer);
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// A unique temporary path beside `target` (same directory, so rename is atomic): ".<name>.tmp.<pid>.<n>".
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

// Removes the temporaries in `dir` left by processes that no longer run (a killed run's partial writes).
// Returns how many were removed.
int remove_stale_temporaries(const std::filesystem::path& dir);

}  // namespace gyrosid
