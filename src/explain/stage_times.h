// Wall time per stage of an explain run (seconds), summed by stage name in the order the stages first ran:
// where a slow recording spends its time (explain.json "stage_times_s", the report's run-time line).
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gyrosid::explain {

struct StageTimes {
  std::vector<std::pair<std::string, double>> seconds;
  void add(std::string_view stage, double s);
};

// Laps of a steady clock: lap(stage) books the time since the previous lap (or construction) to `stage`, and
// prints it as a progress line "<note_prefix><stage>: 1.2 s" (core/progress.h) when the prefix is not empty.
class StageClock {
 public:
  explicit StageClock(StageTimes& times, std::string note_prefix = "")
      : times_(times), note_prefix_(std::move(note_prefix)), last_(std::chrono::steady_clock::now()) {}
  void lap(std::string_view stage);

 private:
  StageTimes& times_;
  std::string note_prefix_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace gyrosid::explain
