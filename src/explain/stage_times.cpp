#include "explain/stage_times.h"

#include <algorithm>

namespace gyrosid::explain {

void StageTimes::add(std::string_view stage, double s) {
  auto it = std::find_if(seconds.begin(), seconds.end(), [&](const auto& p) { return p.first == stage; });
  if (it == seconds.end()) seconds.emplace_back(std::string(stage), s);
  else it->second += s;
}

}  // namespace gyrosid::explain
