#include "nav/monte_carlo.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/distributed.h"
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

namespace {

// Statistics and normality of the first n samples.
void evaluate(MonteCarloResult& r, std::size_t n) {
  for (int c = 0; c < 3; ++c) {
    std::vector<double> x;
    for (std::size_t i = 0; i < n; ++i) x.push_back(r.samples[i](c));
    r.components[static_cast<std::size_t>(c)] = sample_stats(x);
    r.normality[static_cast<std::size_t>(c)] = anderson_darling_normal(x);
  }
  r.normal = r.normality[0].normal_at_5_percent && r.normality[1].normal_at_5_percent && r.normality[2].normal_at_5_percent;
}

// The automatic stop: the first count in (checked, have] on the fixed schedule (min_runs, min_runs + 8, ...)
// at which every component is normal; 0 when none is.
int first_normal_count(MonteCarloResult& r, int checked, int have, const MonteCarloOptions& o) {
  for (int n = o.min_runs; n <= have; n += kCheckEvery) {
    if (n <= checked) continue;
    evaluate(r, static_cast<std::size_t>(n));
    if (r.normal) return n;
  }
  return 0;
}

}  // namespace

MonteCarloResult monte_carlo(const std::function<Eigen::Vector3d(int)>& sample, const MonteCarloOptions& o, const MonteCarloResume& resume) {
  if (auto p = o.validate(); !p.empty()) fail("Monte Carlo: ", p);
  MonteCarloResult r;
  const bool automatic = o.runs == 0;
  const int target = automatic ? o.max_runs : o.runs;
  r.samples = resume.done;
  if (static_cast<int>(r.samples.size()) > target) r.samples.resize(static_cast<std::size_t>(target));
  Progress progress("Monte Carlo", static_cast<std::size_t>(target));
  int checked = 0;  // the stop rule has been applied to every scheduled count up to here
  while (true) {
    const int have = static_cast<int>(r.samples.size());
    if (automatic && have >= o.min_runs) {
      if (const int n = first_normal_count(r, checked, have, o); n > 0) {
        r.samples.resize(static_cast<std::size_t>(n));
        break;
      }
      checked = have;
    }
    if (have >= target) break;
    // Batches grow with the runs done (an eighth of them), so the checkpoint rewrites and the processes'
    // gathers cost O(N log N) over a run, not O(N^2); a kill loses at most an eighth of the work. The
    // stopping schedule above is fixed, so the result does not depend on the batch sizes.
    const int batch = std::max({kCheckEvery, 4 * parallel_width(), have / 8});
    const int want = std::min(target, std::max(have + batch, automatic ? o.min_runs : 0));
    const std::vector<double> rows = map_rows(have, want, 3, [&](int i, double* row) {
      const Eigen::Vector3d e = sample(i);
      row[0] = e(0), row[1] = e(1), row[2] = e(2);
    });
    for (int i = 0; i < want - have; ++i) r.samples.emplace_back(rows[3 * i], rows[3 * i + 1], rows[3 * i + 2]);
    progress.update(r.samples.size());
    if (resume.on_batch) resume.on_batch(r.samples);
  }
  evaluate(r, r.samples.size());
  r.runs = static_cast<int>(r.samples.size());
  Eigen::Vector3d mean(r.components[0].mean, r.components[1].mean, r.components[2].mean);
  r.mean_m = mean.norm();
  r.sigma_m = std::sqrt(r.components[0].sigma * r.components[0].sigma + r.components[1].sigma * r.components[1].sigma +
                        r.components[2].sigma * r.components[2].sigma);
  for (const auto& s : r.samples) r.mean_end_error_m += s.norm() / static_cast<double>(r.runs);
  return r;
}

}  // namespace gyrosid::nav
