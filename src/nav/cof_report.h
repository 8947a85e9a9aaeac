// The criterion-of-fit job behind `gyrosid cof`, the main job and the Table 5.4 experiment: load the
// flight, the sensor and the model, run the deterministic evaluation (model, uncompensated, and the truth
// compensation for scale), optionally the Monte Carlo with the thesis's reference runs, and summarise.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "core/builtin_configs.h"
#include "nav/criterion_of_fit.h"
#include "nav/monte_carlo.h"

namespace gyrosid::nav {

struct CofRequest {
  std::string model = "none";  // a model file, "none" (raw gyro) or "truth" (perfect compensation)
  std::string sensor = kDefaultSensor;
  std::string trajectory = "short";  // short | medium | long | a flight .yaml | a flight .csv
  double rate_hz = 100.0;
  CofOptions options;
  bool monte_carlo = false;
  MonteCarloOptions mc;
  std::uint64_t seed = 1;
  // Kill-safe Monte Carlo: finished runs are saved here after every batch; with `resume` a saved checkpoint
  // of the same computation is continued (the result is identical to an uninterrupted run). The caller
  // removes the file once the outputs are written.
  std::filesystem::path checkpoint;
  bool resume = false;
};

// The thesis's reference runs beside a Monte Carlo (s5.5): white noise alone and a constant bias equal to
// the noise's 1-Hz sigma, neither compensated; sigma_increase is eq 5.2's sqrt(sigma^2 - sigma_noise^2).
struct CofReferenceRuns {
  MonteCarloResult just_noise;
  double bias_dph = 0.0;
  double bias_end_error_m = 0.0;
  double sigma_increase_m = 0.0;
};

// What one criterion-of-fit evaluation found (written as cof.json by report/cof_json.h).
struct CofReport {
  CofRequest request;               // labels, options, seed as evaluated
  FlightTrajectory flight;
  std::vector<NavState> reference;  // the reference INS, every step
  double max_rate_dps = 0.0;
  std::size_t clipped_samples = 0;
  CofRun run, uncompensated;
  Eigen::Vector3d decomposed = Eigen::Vector3d::Zero();  // along-track, cross-track horizontal and vertical, m
  double drift_m_per_h = 0.0;       // error after 1 h, or the end error per hour on shorter flights
  std::optional<MonteCarloResult> mc;
  std::optional<CofReferenceRuns> mc_reference;  // with mc, when the sensor has white noise

  double duration = 0.0;            // of the flight, s
  double duration_s() const { return duration; }
  // Frees the flight and the reference path (large for long flights) once plots no longer need them.
  void drop_paths();
};

// The criterion a flight is scored by: the error after 1 h on flights longer than that (thesis s5.3.3),
// else the end error.
double score_m(const CofRun& run);

FlightTrajectory load_flight(const std::string& name_or_file, double rate_hz);
CofReport evaluate_criterion_of_fit(const CofRequest& request);
// The same with the flight, the sensor and the model already in memory (request.model, .sensor and
// .trajectory are then only labels in the summary).
// `model`: any kind (a single gyro's or a triad's, sensor_model.h); null with mode none or truth.
CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const SensorModel* model, CompensationMode mode,
                       const CofRequest& request);

}  // namespace gyrosid::nav
