// Progress on stderr for anything that may run longer than a few seconds. Silent for the first second
// (short jobs print nothing), then at most twice a second: label, percentage, elapsed and remaining time.
// On a terminal the line is redrawn in place; otherwise a line is printed every 10 %.
// Silenced by set_quiet_progress(true) (`gyrosid --quiet`) or by GYROSID_QUIET=1 in the environment (tests
// set it); the setter wins over the environment.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace gyrosid {

void set_quiet_progress(bool quiet);

// While one lives, Progress and progress_note are silent on the thread that made it: for jobs run side by side,
// whose own lines would interleave, and whose caller reports their progress as one.
class ProgressSilenced {
 public:
  ProgressSilenced();
  ~ProgressSilenced();
  ProgressSilenced(const ProgressSilenced&) = delete;
  ProgressSilenced& operator=(const ProgressSilenced&) = delete;
};

// One plain line on stderr for a stage of a long command, e.g. "explain: selection step 1: 2 candidates" or
// "explain: refit: 5.2 s", on a terminal or not; silenced like Progress.
void progress_note(std::string_view text);

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void update(std::size_t done);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  int last_decile_ = -1;
  bool printed_ = false;
  bool finished_ = false;
  bool tty_ = false;
  bool quiet_ = false;
};

}  // namespace gyrosid
