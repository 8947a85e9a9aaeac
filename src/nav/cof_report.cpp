#include "nav/cof_report.h"

#include <cmath>
#include <cstring>
#include <utility>

#include "core/config.h"
#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "sensor/sensor_config.h"

namespace gyrosid::nav {

FlightTrajectory load_flight(const std::string& name, double rate_hz) {
  const auto ends_with = [&](const char* s) { return name.size() > std::strlen(s) && name.ends_with(s); };
  if (ends_with(".csv")) return load_flight_csv(name);
  if (ends_with(".yaml") || ends_with(".yml") || name.rfind("builtin:", 0) == 0) {
    return generate_flight(load_flight_profile(ConfigNode::load(name)), rate_hz);
  }
  return generate_flight(builtin_flight(name), rate_hz);
}

CofReport evaluate_criterion_of_fit(const CofRequest& r) {
  std::unique_ptr<CalibrationModel> model;
  CompensationMode mode = CompensationMode::model;
  if (r.model == "none") mode = CompensationMode::none;
  else if (r.model == "truth") mode = CompensationMode::truth;
  else if (is_triad_model_file(r.model)) return score_flight(load_flight(r.trajectory, r.rate_hz), as_triad(load_sensor_file(r.sensor)), load_triad_model(r.model), r);
  else model = load_model(r.model);
  return score_flight(load_flight(r.trajectory, r.rate_hz), as_triad(load_sensor_file(r.sensor)), model.get(), mode, r);
}

void CofReport::drop_paths() {
  reference = {};
  flight = FlightTrajectory{};
}

double score_m(const CofRun& run) { return std::isnan(run.error_after_1h_m) ? run.end_error_m : run.error_after_1h_m; }

namespace {

// The Monte Carlo of `mode` with new noise every run, and the thesis's reference runs beside it.
void run_monte_carlo(const CofEvaluator& cof, const TriadSensor& sensor, CompensationMode mode, const CofRequest& r, CofReport& report) {
  const std::uint64_t base = r.seed;
  report.mc = monte_carlo([&](int i) {
    return cof.decompose(cof.run(mode, true, base ^ hash_name("mc/" + std::to_string(i)), false).error_ned);
  }, r.mc);
  const double sigma = sensor.gyros[0].noise.arw_rad_rt_s;  // white-noise sigma at 1 Hz, rad/s
  if (!(sigma > 0)) return;
  CofReferenceRuns ref;
  ref.just_noise = monte_carlo([&](int i) {
    return cof.decompose(cof.run_reference(sigma, 0.0, base ^ hash_name("noise/" + std::to_string(i))).error_ned);
  }, r.mc);
  ref.bias_dph = units::radps_to_dph(sigma);
  ref.bias_end_error_m = cof.run_reference(0.0, sigma, base).end_error_m;
  const double inc2 = report.mc->sigma_m * report.mc->sigma_m - ref.just_noise.sigma_m * ref.just_noise.sigma_m;
  ref.sigma_increase_m = inc2 > 0 ? std::sqrt(inc2) : 0.0;  // thesis eq 5.2
  report.mc_reference = std::move(ref);
}

// Fills `report` (whose flight the evaluator reads) with the runs of `cof`.
void score(CofReport& report, const CofEvaluator& cof, const TriadSensor& sensor, CompensationMode mode, const CofRequest& r) {
  report.reference = cof.reference_path();
  report.duration = cof.duration_s();
  report.max_rate_dps = cof.max_abs_rate_dps();
  report.clipped_samples = cof.clipped_samples();
  report.run = cof.run(mode, false, r.seed, true);
  report.uncompensated = cof.run(CompensationMode::none, false, r.seed, true);
  report.decomposed = cof.decompose(report.run.error_ned);
  const double hours = cof.duration_s() / 3600.0;
  report.drift_m_per_h = std::isnan(report.run.error_after_1h_m) ? report.run.end_error_m / hours : report.run.error_after_1h_m;
  if (r.monte_carlo) run_monte_carlo(cof, sensor, mode, r, report);
}

}  // namespace

CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const CalibrationModel* model,
                       CompensationMode mode, const CofRequest& r) {
  CofReport report;
  report.request = r;
  report.flight = std::move(flight);
  const CofEvaluator cof(report.flight, sensor, model, r.options);
  score(report, cof, sensor, mode, r);
  return report;
}

CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const TriadModel& triad, const CofRequest& r) {
  CofReport report;
  report.request = r;
  report.flight = std::move(flight);
  const CofEvaluator cof(report.flight, sensor, triad, r.options);
  score(report, cof, sensor, CompensationMode::model, r);
  return report;
}

}  // namespace gyrosid::nav
