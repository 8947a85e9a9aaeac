#include "nav/cof_report.h"

#include <cmath>
#include <cstring>
#include <utility>

#include "core/checkpoint.h"
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
  std::unique_ptr<SensorModel> model;
  CompensationMode mode = CompensationMode::model;
  if (r.model == "none") mode = CompensationMode::none;
  else if (r.model == "truth") mode = CompensationMode::truth;
  else model = load_sensor_model(r.model);
  return score_flight(load_flight(r.trajectory, r.rate_hz), as_triad(load_sensor_file(r.sensor)), model.get(), mode, r);
}

void CofReport::drop_paths() {
  reference = {};
  flight = FlightTrajectory{};
}

double score_m(const CofRun& run) { return std::isnan(run.error_after_1h_m) ? run.end_error_m : run.error_after_1h_m; }

namespace {

// What a Monte Carlo computes: the flight, the model, the sensor config, the options and the seed.
std::string fingerprint(const FlightTrajectory& flight, const std::string& model_text, CompensationMode mode, const CofRequest& r) {
  std::string sensor_text;
  try {
    sensor_text = config_text(r.sensor);
  } catch (const Error&) {
    sensor_text = r.sensor;  // an in-memory sensor: its label
  }
  const auto bytes = [](const std::vector<Eigen::Vector3d>& v) {
    return std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(Eigen::Vector3d));
  };
  return digest(str_cat(digest(bytes(flight.dtheta)), digest(bytes(flight.dv)), flight.dt_s, "|",
                        digest(model_text), "|", static_cast<int>(mode), "|",
                        digest(sensor_text), "|", r.rate_hz, r.options.start_temp_c, r.options.thermal_delay_s,
                        static_cast<int>(r.options.probe), r.options.clip_rate_dps, r.options.scale_rates, "|", r.mc.runs,
                        r.mc.min_runs, r.mc.max_runs, "|", r.seed));
}

// Runs saved in a checkpoint series (3 values per run) and the hook that saves them after every batch.
MonteCarloResume resume_from(Checkpoint& checkpoint, const std::string& series) {
  MonteCarloResume m;
  const std::vector<double>& v = checkpoint.series(series);
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) m.done.emplace_back(v[i], v[i + 1], v[i + 2]);
  m.on_batch = [&checkpoint, series](const std::vector<Eigen::Vector3d>& all) {
    std::vector<double> flat;
    for (const auto& e : all) flat.insert(flat.end(), {e(0), e(1), e(2)});
    checkpoint.save(series, std::move(flat));
  };
  return m;
}

// The Monte Carlo of `mode` with new noise every run, and the thesis's reference runs beside it.
void run_monte_carlo(const CofEvaluator& cof, const TriadSensor& sensor, const std::string& model_text, CompensationMode mode,
                     const CofRequest& r, CofReport& report) {
  const std::uint64_t base = r.seed;
  Checkpoint checkpoint = r.checkpoint.empty() ? Checkpoint() : Checkpoint(r.checkpoint, fingerprint(report.flight, model_text, mode, r), r.resume);
  report.mc = monte_carlo([&](int i) {
    return cof.decompose(cof.run(mode, true, base ^ hash_name("mc/" + std::to_string(i)), false).error_ned);
  }, r.mc, resume_from(checkpoint, "mc"));
  const double sigma = sensor.gyros[0].noise.arw_rad_rt_s;  // white-noise sigma at 1 Hz, rad/s
  if (!(sigma > 0)) return;
  CofReferenceRuns ref;
  ref.just_noise = monte_carlo([&](int i) {
    return cof.decompose(cof.run_reference(sigma, 0.0, base ^ hash_name("noise/" + std::to_string(i))).error_ned);
  }, r.mc, resume_from(checkpoint, "noise"));
  ref.bias_dph = units::radps_to_dph(sigma);
  ref.bias_end_error_m = cof.run_reference(0.0, sigma, base).end_error_m;
  const double inc2 = report.mc->sigma_m * report.mc->sigma_m - ref.just_noise.sigma_m * ref.just_noise.sigma_m;
  ref.sigma_increase_m = inc2 > 0 ? std::sqrt(inc2) : 0.0;  // thesis eq 5.2
  report.mc_reference = std::move(ref);
}

// Fills `report` (whose flight the evaluator reads) with the runs of `cof`.
void score(CofReport& report, const CofEvaluator& cof, const TriadSensor& sensor, const std::string& model_text,
           CompensationMode mode, const CofRequest& r) {
  report.reference = cof.reference_path();
  report.duration = cof.duration_s();
  report.max_rate_dps = cof.max_abs_rate_dps();
  report.clipped_samples = cof.clipped_samples();
  report.run = cof.run(mode, false, r.seed, true);
  report.uncompensated = cof.run(CompensationMode::none, false, r.seed, true);
  report.decomposed = cof.decompose(report.run.error_ned);
  const double hours = cof.duration_s() / 3600.0;
  report.drift_m_per_h = std::isnan(report.run.error_after_1h_m) ? report.run.end_error_m / hours : report.run.error_after_1h_m;
  if (r.monte_carlo) run_monte_carlo(cof, sensor, model_text, mode, r, report);
}

}  // namespace

CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const SensorModel* model, CompensationMode mode,
                       const CofRequest& r) {
  CofReport report;
  report.request = r;
  report.flight = std::move(flight);
  const CofEvaluator cof(report.flight, sensor, model, r.options);
  score(report, cof, sensor, model ? model->to_json().dump() : std::string("none"), mode, r);
  return report;
}

}  // namespace gyrosid::nav
