#include "pipeline/main_job.h"

#include <chrono>
#include <iostream>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "report/cof_plots.h"
#include "report/plots.h"
#include "sensor/error_surface.h"
#include "sim/simulate.h"

namespace gyrosid {

std::string MainJobOptions::validate() const {
  if (out.empty()) return "out: an output directory is required";
  if (flights.empty()) return "flights: at least one flight is required";
  if (!std::isfinite(start_temp_c)) return "start_temp_c must be finite";
  return "";
}

std::string MainJobOptions::rbf_config_used() const {
  if (!rbf_config.empty()) return rbf_config;
  return noisy ? "builtin:calibration/rbf_noisy.yaml" : "builtin:calibration/rbf_noise_free.yaml";
}

namespace {

constexpr int kSteps = 7;

class Steps {
 public:
  explicit Steps(const MainJobOptions& o) : on_step_(o.on_step) {}
  void next(const std::string& what) {
    ++done_;
    if (on_step_) on_step_(done_, kSteps, what);
    else std::cerr << "[" << done_ << "/" << kSteps << "] " << what << std::endl;
  }

 private:
  std::function<void(int, int, const std::string&)> on_step_;
  int done_ = 0;
};

CalibratedModel calibrate_on(const std::string& label, const Recording& recording, const std::string& config,
                             const std::filesystem::path& dir) {
  CalibratedModel c{label, config, calibrate(recording, calibration_request_from_config(ConfigNode::load(config))), {}};
  c.result.training["config"] = config;
  save_model(dir / "models" / (label + ".json"), *c.result.model, {{"training", c.result.training}, {"summary", c.result.summary}});
  return c;
}

void compare_with_truth(CalibratedModel& c, const GyroSensor& truth, const SurfaceGridSpec& grid, const std::filesystem::path& dir) {
  c.surface = compare_surfaces(*c.result.model, truth, grid);
  plot_grid_surface(dir / "surfaces" / (c.label + "_difference.png"), c.surface.temps_c, c.surface.rates_dps, c.surface.difference_dph(),
                    c.label + ": estimated - true rate error (rms " + format_significant(c.surface.stats.rms_dph, 3) + " deg/h)",
                    "difference (deg/h)");
  if (c.surface.sigma_dph.size() > 0) {  // a model with a posterior: its predictive sigma beside the error
    plot_grid_surface(dir / "surfaces" / (c.label + "_sigma.png"), c.surface.temps_c, c.surface.rates_dps, c.surface.sigma_dph,
                      c.label + ": predictive sigma (rms " + format_significant(c.surface.sigma_stats.rms_sigma_dph, 3) + " deg/h, 95 % band covers " +
                          format_significant(100 * c.surface.sigma_stats.coverage_95, 3) + " %)",
                      "sigma (deg/h)");
  }
}

// Step 2: the noise of a static run (gyro - reference), Allan deviation.
AllanReport characterise_noise(const MainJobOptions& o, const SensorSpec& sensor, MainJobResult& result) {
  const Simulation still = simulate(sensor, load_trajectory_file(o.static_trajectory), o.seed);
  result.static_description = describe(still);
  std::vector<double> noise = rate_column_dph(still.recording, "gyro_dps");
  const std::vector<double> ref = rate_column_dph(still.recording, "ref_rate_dps");
  for (std::size_t i = 0; i < noise.size(); ++i) noise[i] -= ref[i];
  return write_allan(o.out / "allan", noise, uniform_sample_interval(still.recording, "the Allan deviation"), AllanOptions{}, NoiseIdOptions{},
                     "Allan deviation of the static run (gyro - reference)", {{"recording", "simulated static run"}, {"unit", "deg/h"}});
}

nav::CofRequest flight_request(const MainJobOptions& o, const std::string& flight, const std::string& model) {
  nav::CofRequest request;
  request.sensor = o.sensor, request.trajectory = flight, request.seed = o.seed, request.model = model;
  request.options.start_temp_c = o.start_temp_c;
  return request;
}

// Step 5: both models on every flight, noise off; outputs per flight and model under cof/.
void score_flights(const MainJobOptions& o, const TriadSensor& triad, MainJobResult& result) {
  for (const auto& name : o.flights) {
    const FlightTrajectory flight = nav::load_flight(name, nav::CofRequest{}.rate_hz);
    auto score = [&](const CalibratedModel& c) {
      nav::CofReport r = nav::score_flight(flight, triad, c.result.model.get(), nav::CompensationMode::model, flight_request(o, name, c.label));
      write_cof_outputs(r, o.out / "cof" / name / c.label);
      return r;
    };
    FlightScores s{name, score(result.classical), score(result.rbf)};
    plot_error_growth(o.out / "cof" / (name + "_error_growth.png"), "Position error on the " + name + " flight",
                      {{"uncompensated", &s.rbf.uncompensated}, {"classical", &s.classical.run}, {"RBF", &s.rbf.run}});
    s.classical.drop_paths();
    s.rbf.drop_paths();
    std::cerr << "      " << name << ": classical " << format_significant(nav::score_m(s.classical.run), 3) << " m, RBF "
              << format_significant(nav::score_m(s.rbf.run), 3) << " m" << std::endl;
    result.flights.push_back(std::move(s));
  }
}

// Step 6: Monte Carlo on the short flight with the sensor's noise, until normal (Anderson-Darling).
void short_monte_carlo(const MainJobOptions& o, const TriadSensor& triad, MainJobResult& result) {
  for (const CalibratedModel* c : {&result.classical, &result.rbf}) {
    nav::CofRequest request = flight_request(o, "short", c->label);
    request.monte_carlo = true;
    request.mc.runs = 0;  // auto
    nav::CofReport r = nav::score_flight(nav::load_flight("short", request.rate_hz), triad, c->result.model.get(),
                                         nav::CompensationMode::model, request);
    write_cof_outputs(r, o.out / "cof" / "short_monte_carlo" / c->label);
    r.drop_paths();
    result.short_monte_carlo.push_back(std::move(r));
  }
}

}  // namespace

MainJobResult run_main_job(const MainJobOptions& o) {
  if (const std::string problem = o.validate(); !problem.empty()) fail("main job: ", problem);
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path& dir = o.out;
  Steps steps(o);
  MainJobResult result;

  steps.next(std::string("simulating the sensor on the dual scan and the classical soak (") + (o.noisy ? "with" : "without") + " noise)");
  const SensorSpec sensor = load_sensor_file(o.sensor);
  if (!std::holds_alternative<GyroSensor>(sensor)) fail("the main job calibrates one gyro: '", o.sensor, "' is a triad; give a single-gyro sensor config");
  const SensorSpec calibration_sensor = o.noisy ? sensor : without_noise(sensor);
  const Simulation dual = simulate(calibration_sensor, load_trajectory_file(o.trajectory), o.seed);
  const Simulation soak = simulate(calibration_sensor, load_trajectory_file(o.soak), o.seed);
  result.dual_description = describe(dual), result.soak_description = describe(soak);
  write_recording(dual.recording, dir / "data" / "dual_scan.csv");
  write_recording(soak.recording, dir / "data" / "classical_soak.csv");
  const GyroSensor& truth = representative_gyro(sensor);
  plot_surface(dir / "error_surface.png", error_surface_dps(truth), kPlotSurfaceGrid,
               "True rate error of '" + truth.name + "' (steady temperature)", "rate error (deg/s)");
  plot_coverage(dir / "coverage.png", dual.recording.column("temp_c"), dual.recording.column("ref_rate_dps"),
                "Samples of " + dual.trajectory.profile.name + " over (T, omega)");

  steps.next("characterising the noise on a static run (Allan deviation)");
  result.allan = characterise_noise(o, sensor, result);

  steps.next("calibrating the classical model on the soak (" + o.classical_config + ")");
  result.classical = calibrate_on("classical", soak.recording, o.classical_config, dir);
  steps.next("calibrating the RBF network on the dual scan (" + o.rbf_config_used() + ")");
  result.rbf = calibrate_on("rbf", dual.recording, o.rbf_config_used(), dir);
  const SurfaceGridSpec grid = comparison_grid(truth, {result.classical.result.training, result.rbf.result.training});
  compare_with_truth(result.classical, truth, grid, dir);
  compare_with_truth(result.rbf, truth, grid, dir);

  steps.next("criterion of fit on the flights: " + join(o.flights));
  const TriadSensor triad = as_triad(sensor);
  score_flights(o, triad, result);
  steps.next("Monte Carlo on the short flight with the sensor's noise (Anderson-Darling stopping)");
  short_monte_carlo(o, triad, result);

  steps.next("writing the report");
  result.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_main_job_report(o, result);
  return result;
}

}  // namespace gyrosid
