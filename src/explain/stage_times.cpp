#include "explain/stage_times.h"

#include <algorithm>

#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"

namespace gyrosid::explain {

void StageTimes::add(std::string_view stage, double s) {
  auto it = std::find_if(seconds.begin(), seconds.end(), [&](const auto& p) { return p.first == stage; });
  if (it == seconds.end()) seconds.emplace_back(std::string(stage), s);
  else it->second += s;
}

void StageClock::lap(std::string_view stage) {
  const auto now = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(now - last_).count();
  times_.add(stage, s);
  last_ = now;
  if (!note_prefix_.empty()) progress_note(str_cat(note_prefix_, stage, ": ", format_significant(s, 3), " s"));
}

}  // namespace gyrosid::explain
