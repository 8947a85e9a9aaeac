// Monte Carlo evaluation of the criterion of fit (thesis fig 5.18): new noise every run, runs spread over
// all cores in batches, deterministic per seed (run i always draws from seed i whatever the thread count).
// With runs = 0 it stops when the Anderson-Darling test accepts normality of every error component at 5 %
// (at least `min_runs`, thesis s5.5) or at `max_runs`. Components are along-track and the two cross-track
// errors (fig 5.19); the combined spread is sigma_tot = sqrt(sigma_x^2 + sigma_y^2 + sigma_z^2) (eq 5.1).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "nav/statistics.h"

namespace gyrosid::nav {

struct MonteCarloOptions {
  int runs = 0;        // 0: until normal (Anderson-Darling), else exactly this many
  int min_runs = 25;
  int max_runs = 1000;
  std::string validate() const;
};

struct MonteCarloResult {
  int runs = 0;
  std::array<SampleStats, 3> components;  // along, cross-h, cross-v
  std::array<AndersonDarling, 3> normality;
  bool normal = false;                    // every component accepted at 5 %
  double mean_m = 0.0;                    // |mean error vector|
  double sigma_m = 0.0;                   // eq 5.1
  double mean_end_error_m = 0.0;          // mean of |error| (for reference; biased by the modulus)
  std::vector<Eigen::Vector3d> samples;
  nlohmann::json to_json() const;
};

// Runs already computed (from a checkpoint) and a hook after every batch (to save one), so that a killed
// Monte Carlo resumes where it stopped and ends identical to an uninterrupted one.
struct MonteCarloResume {
  std::vector<Eigen::Vector3d> done;  // runs 0..k-1
  std::function<void(const std::vector<Eigen::Vector3d>& all)> on_batch;
};

// `sample(i)` returns run i's decomposed error (along, cross-h, cross-v). Called concurrently, by the threads
// of this process or across processes (core/distributed.h). Runs are computed in batches that scale with the
// parallelism, but the normality test of the automatic stop is applied at fixed counts (min_runs, then every
// kCheckEvery runs), so the number of runs and every figure are the same whatever the thread or process count.
inline constexpr int kCheckEvery = 8;
MonteCarloResult monte_carlo(const std::function<Eigen::Vector3d(int run)>& sample, const MonteCarloOptions& options,
                             const MonteCarloResume& resume = {});

}  // namespace gyrosid::nav
