// The criterion-of-fit job behind `gyrosid cof`, the main job and the Table 5.4 experiment: load the
// flight, the sensor and the model, run the deterministic evaluation (model, uncompensated, and the truth
// compensation for scale), optionally the Monte Carlo with the thesis's reference runs, and summarise.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "nav/criterion_of_fit.h"
#include "nav/monte_carlo.h"

namespace gyrosid::nav {

struct CofRequest {
  std::string model = "none";  // a model file, "none" (raw gyro) or "truth" (perfect compensation)
  std::string sensor = "builtin:sensors/open_loop_fog.yaml";
  std::string trajectory = "short";  // short | medium | long | a flight .yaml | a flight .csv
  double rate_hz = 100.0;
  CofOptions options;
  bool monte_carlo = false;
  MonteCarloOptions mc;
  std::uint64_t seed = 1;
};

struct CofReport {
  nlohmann::json summary;  // cof.json
  FlightTrajectory flight;
  std::vector<NavState> reference;
  CofRun run, uncompensated;
  std::optional<MonteCarloResult> mc;
};

FlightTrajectory load_flight(const std::string& name_or_file, double rate_hz);
CofReport evaluate_criterion_of_fit(const CofRequest& request);
// The same with the flight, the sensor and the model already in memory (request.model, .sensor and
// .trajectory are then only labels in the summary).
CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const CalibrationModel* model,
                       CompensationMode mode, const CofRequest& request);

}  // namespace gyrosid::nav
