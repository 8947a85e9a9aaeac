#include "nav/monte_carlo.h"

#include <cmath>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace gyrosid::nav {

std::string MonteCarloOptions::validate() const {
  if (runs < 0) return "runs must be >= 0 (0: stop by the Anderson-Darling test)";
  if (runs > 0 && runs < 8) return "at least 8 runs are needed for the normality test";
  if (min_runs < 8) return "min_runs must be at least 8";
  if (max_runs < min_runs) return "max_runs must be >= min_runs";
  return "";
}

nlohmann::json MonteCarloResult::to_json() const {
  const char* names[] = {"along_track", "cross_track_horizontal", "cross_track_vertical"};
  nlohmann::json comps = nlohmann::json::object();
  for (int i = 0; i < 3; ++i) {
    comps[names[i]] = {{"mean_m", components[static_cast<std::size_t>(i)].mean},
                       {"sigma_m", components[static_cast<std::size_t>(i)].sigma},
                       {"anderson_darling_a2", normality[static_cast<std::size_t>(i)].a2_adjusted},
                       {"anderson_darling_p", normality[static_cast<std::size_t>(i)].p_value},
                       {"normal", normality[static_cast<std::size_t>(i)].normal_at_5_percent}};
  }
  return {{"runs", runs}, {"mean_m", mean_m}, {"sigma_m", sigma_m}, {"anderson_darling_accepted", normal},
          {"mean_end_error_m", mean_end_error_m}, {"components", comps}};
}

MonteCarloResult monte_carlo(const std::function<Eigen::Vector3d(int)>& sample, const MonteCarloOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("Monte Carlo: ", p);
  MonteCarloResult r;
  const int target = o.runs > 0 ? o.runs : o.max_runs;
  const int batch = std::max(8, 4 * worker_threads());
  Progress progress("Monte Carlo", static_cast<std::size_t>(target));
  auto evaluate = [&]() {
    for (int c = 0; c < 3; ++c) {
      std::vector<double> x;
      for (const auto& s : r.samples) x.push_back(s(c));
      r.components[static_cast<std::size_t>(c)] = sample_stats(x);
      r.normality[static_cast<std::size_t>(c)] = anderson_darling_normal(x);
    }
    r.normal = r.normality[0].normal_at_5_percent && r.normality[1].normal_at_5_percent && r.normality[2].normal_at_5_percent;
  };
  while (static_cast<int>(r.samples.size()) < target) {
    const int have = static_cast<int>(r.samples.size());
    const int want = have < o.min_runs && o.runs == 0 ? o.min_runs : std::min(target, have + batch);
    std::vector<Eigen::Vector3d> fresh(static_cast<std::size_t>(want - have));
    parallel_for(want - have, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      for (std::ptrdiff_t i = b; i < e; ++i) fresh[static_cast<std::size_t>(i)] = sample(have + static_cast<int>(i));
    });
    r.samples.insert(r.samples.end(), fresh.begin(), fresh.end());
    progress.update(r.samples.size());
    if (o.runs == 0 && static_cast<int>(r.samples.size()) >= o.min_runs) {
      evaluate();
      if (r.normal) break;
    }
  }
  evaluate();
  r.runs = static_cast<int>(r.samples.size());
  Eigen::Vector3d mean(r.components[0].mean, r.components[1].mean, r.components[2].mean);
  r.mean_m = mean.norm();
  r.sigma_m = std::sqrt(r.components[0].sigma * r.components[0].sigma + r.components[1].sigma * r.components[1].sigma +
                        r.components[2].sigma * r.components[2].sigma);
  for (const auto& s : r.samples) r.mean_end_error_m += s.norm() / static_cast<double>(r.runs);
  return r;
}

}  // namespace gyrosid::nav
