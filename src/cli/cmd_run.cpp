// gyrosid run: the main job - the thesis's pipeline end to end on the built-in default configuration
// (simulated reference sensor, no outside data):
//   1. simulate the sensor on the classical soak (Table 2.1 positions at 20 C plateaus, s5.3.2) and on the
//      dual scan (s4.3), noise-free as the thesis's Table 5.4 unless --noisy;
//   2. plot the true error surface and the dual scan's coverage; characterise the noise on a static run;
//   3. calibrate the classical model on the soak and the RBF network on the dual scan;
//   4. compare both with the true surface (Tables 5.2/5.3) and score both by the criterion of fit on the
//      short, medium and long flights (Table 5.4), with a Monte Carlo on the short flight (s5.5);
//   5. write report.md (tables, plots) and summary.json.
#include <chrono>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/app.h"
#include "cli/common.h"
#include "core/atomic_file.h"
#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/surface_comparison.h"
#include "nav/cof_report.h"
#include "report/cof_plots.h"
#include "report/plots.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"

namespace gyrosid::cli {
namespace {

struct RunOptions {
  std::string out = "report";
  std::string sensor = kDefaultSensor;
  std::string trajectory = kDefaultTrajectory;
  std::string soak = "builtin:trajectories/classical_soak.yaml";
  std::string static_trajectory = kStaticTrajectory;
  std::string classical_config = "builtin:calibration/classical.yaml";
  std::string rbf_config;  // default: rbf_noise_free.yaml, or rbf_noisy.yaml with --noisy
  std::vector<std::string> flights = {"short", "medium", "long"};
  double start_temp_c = 10.0;
  bool noisy = false;
  std::uint64_t seed = 1;
};

class Steps {
 public:
  explicit Steps(int total) : total_(total) {}
  void next(const std::string& what) { std::cerr << "[" << ++done_ << "/" << total_ << "] " << what << std::endl; }

 private:
  int total_, done_ = 0;
};

struct Calibrated {
  std::string label;
  CalibrationResult result;
  SurfaceComparison surface;
};

Calibrated calibrate_on(const std::string& label, const Recording& recording, const std::string& config,
                        const std::filesystem::path& dir) {
  Calibrated c{label, calibrate(recording, calibration_request_from_config(ConfigNode::load(config))), {}};
  c.result.training["config"] = config;
  save_model(dir / "models" / (label + ".json"), *c.result.model, {{"training", c.result.training}, {"summary", c.result.summary}});
  return c;
}

void compare_with_truth(Calibrated& c, const GyroSensor& truth, const SurfaceGridSpec& grid, const std::filesystem::path& dir) {
  const std::string& label = c.label;
  c.surface = compare_surfaces(*c.result.model, truth, grid);
  plot_grid_surface(dir / "surfaces" / (label + "_difference.png"), c.surface.temps_c, c.surface.rates_dps, c.surface.difference_dph(),
                    label + ": estimated - true rate error (rms " + format_significant(c.surface.stats.rms_dph, 3) + " deg/h)",
                    "difference (deg/h)");
}

// Long flights are scored after 1 h (thesis s5.3.3), shorter ones at their end.
double score_m(const nlohmann::json& cof) { return cof.value("error_after_1h_m", cof["end_error_m"].get<double>()); }

std::string cell(double v) { return format_significant(v, 3); }

void run_main(const RunOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path dir = o.out;
  const std::string rbf_config = !o.rbf_config.empty() ? o.rbf_config
                                 : o.noisy          ? "builtin:calibration/rbf_noisy.yaml"
                                                    : "builtin:calibration/rbf_noise_free.yaml";
  Steps steps(7);

  steps.next(std::string("simulating the sensor on the dual scan and the classical soak (") + (o.noisy ? "with" : "without") + " noise)");
  const SensorSpec sensor = load_sensor_file(o.sensor);
  const SensorSpec calibration_sensor = o.noisy ? sensor : without_noise(sensor);
  const Simulation dual = simulate(calibration_sensor, load_trajectory_file(o.trajectory), o.seed);
  const Simulation soak = simulate(calibration_sensor, load_trajectory_file(o.soak), o.seed);
  write_recording(dual.recording, dir / "data" / "dual_scan.csv");
  write_recording(soak.recording, dir / "data" / "classical_soak.csv");
  const GyroSensor& truth = representative_gyro(sensor);
  plot_surface(dir / "error_surface.png", error_surface_dps(truth), SurfaceGrid{},
               "True rate error of '" + truth.name + "' (steady temperature)", "rate error (deg/s)");
  const bool single = dual.recording.kind() == RecordingKind::single;
  if (!single) fail("the main job calibrates one gyro: '", o.sensor, "' is a triad; give a single-gyro sensor config");
  plot_coverage(dir / "coverage.png", dual.recording.column("temp_c"), dual.recording.column("ref_rate_dps"),
                "Samples of " + dual.trajectory.profile.name + " over (T, omega)");

  steps.next("characterising the noise on a static run (Allan deviation)");
  const Simulation still = simulate(sensor, load_trajectory_file(o.static_trajectory), o.seed);
  std::vector<double> noise = rate_column_dph(still.recording, "gyro_dps");
  const std::vector<double> ref = rate_column_dph(still.recording, "ref_rate_dps");
  for (std::size_t i = 0; i < noise.size(); ++i) noise[i] -= ref[i];
  const AllanReport allan = write_allan(dir / "allan", noise, uniform_sample_interval(still.recording, "the Allan deviation"),
                                        AllanOptions{}, "Allan deviation of the static run (gyro - reference)",
                                        {{"recording", "simulated static run"}, {"unit", "deg/h"}});

  steps.next("calibrating the classical model on the soak (" + o.classical_config + ")");
  Calibrated classical = calibrate_on("classical", soak.recording, o.classical_config, dir);
  steps.next("calibrating the RBF network on the dual scan (" + rbf_config + ")");
  Calibrated rbf = calibrate_on("rbf", dual.recording, rbf_config, dir);
  const SurfaceGridSpec grid = comparison_grid(truth, {classical.result.training, rbf.result.training});
  compare_with_truth(classical, truth, grid, dir);
  compare_with_truth(rbf, truth, grid, dir);

  steps.next("criterion of fit on the flights: " + [&] { std::string s; for (const auto& f : o.flights) s += (s.empty() ? "" : ", ") + f; return s; }());
  const TriadSensor triad = as_triad(sensor);
  struct FlightScores { std::string flight; double duration_s; nlohmann::json none, classical, rbf; };
  std::vector<FlightScores> scores;
  for (const auto& name : o.flights) {
    nav::CofRequest request;
    request.sensor = o.sensor, request.trajectory = name, request.seed = o.seed;
    request.options.start_temp_c = o.start_temp_c;
    const FlightTrajectory flight = nav::load_flight(name, request.rate_hz);
    auto score = [&](const std::string& label, const CalibrationModel* model) {
      request.model = label;
      return nav::score_flight(flight, triad, model, model ? nav::CompensationMode::model : nav::CompensationMode::none, request);
    };
    const nav::CofReport with_classical = score("classical", classical.result.model.get());
    const nav::CofReport with_rbf = score("rbf", rbf.result.model.get());
    write_cof_outputs(with_classical, dir / "cof" / name / "classical");
    write_cof_outputs(with_rbf, dir / "cof" / name / "rbf");
    plot_error_growth(dir / "cof" / (name + "_error_growth.png"), "Position error on the " + name + " flight",
                      {{"uncompensated", &with_rbf.uncompensated}, {"classical", &with_classical.run}, {"RBF", &with_rbf.run}});
    nlohmann::json none = {{"end_error_m", with_rbf.uncompensated.end_error_m}};
    if (!std::isnan(with_rbf.uncompensated.error_after_1h_m)) none["error_after_1h_m"] = with_rbf.uncompensated.error_after_1h_m;
    scores.push_back({name, flight.duration_s(), none, with_classical.summary, with_rbf.summary});
    std::cerr << "      " << name << ": classical " << cell(score_m(with_classical.summary)) << " m, RBF "
              << cell(score_m(with_rbf.summary)) << " m" << std::endl;
  }

  steps.next("Monte Carlo on the short flight with the sensor's noise (Anderson-Darling stopping)");
  nlohmann::json mc;
  for (const Calibrated* c : {&classical, &rbf}) {
    nav::CofRequest request;
    request.sensor = o.sensor, request.trajectory = "short", request.seed = o.seed, request.model = c->label;
    request.options.start_temp_c = o.start_temp_c;
    request.monte_carlo = true;
    request.mc.runs = 0;  // auto
    const nav::CofReport r = nav::score_flight(nav::load_flight("short", request.rate_hz), triad, c->result.model.get(),
                                               nav::CompensationMode::model, request);
    write_cof_outputs(r, dir / "cof" / "short_monte_carlo" / c->label);
    mc[c->label] = r.summary["monte_carlo"];
  }

  steps.next("writing the report");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json summary = {{"sensor", o.sensor}, {"calibration_noise", o.noisy}, {"seed", o.seed}, {"run_time_s", seconds},
                            {"start_temp_c", o.start_temp_c}, {"monte_carlo_short", mc}};
  std::ostringstream md;
  md << "# gyrosid main job\n\n"
     << "The thesis's pipeline (du Plessis 2013, ch. 5) on the built-in default configuration: sensor `" << o.sensor
     << "`, seed " << o.seed << ", calibration recordings " << (o.noisy ? "with" : "without") << " sensor noise"
     << (o.noisy ? "" : " (as the thesis's Table 5.4; `--noisy` for the other case)") << ". Run time "
     << format_number(std::round(seconds * 10) / 10) << " s.\n\n"
     << "## Calibration data\n\n"
     << "- dual scan: " << describe(dual) << " (`data/dual_scan.csv`)\n"
     << "- classical soak: " << describe(soak) << " (`data/classical_soak.csv`)\n\n"
     << "![error surface](error_surface.png)\n\n![coverage](coverage.png)\n\n"
     << "## Models against the true error surface (cf. Tables 5.2/5.3)\n\n"
     << "Estimated minus true rate error over T " << cell(rbf.surface.temps_c.front()) << ".." << cell(rbf.surface.temps_c.back())
     << " C x omega -100..100 deg/s, deg/h.\n\n"
     << "| model | config | parameters | fit time (s) | mean | sigma | max | min | rms |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const Calibrated* c : {&classical, &rbf}) {
    const auto& s = c->surface.stats;
    const auto& fit = c->result.summary;
    const std::string params = fit.details.contains("nodes") ? std::to_string(fit.details["nodes"].get<int>()) + " nodes"
                                                             : std::to_string(fit.details.value("parameters", 0)) + " coefficients";
    md << "| " << c->label << " | `" << c->result.training["config"].get<std::string>() << "` | " << params << " | "
       << cell(fit.time_s) << " | " << cell(s.mean_dph) << " | " << cell(s.sigma_dph) << " | "
       << cell(s.max_dph) << " | " << cell(s.min_dph) << " | " << cell(s.rms_dph) << " |\n";
    summary["models"][c->label] = {{"config", c->result.training["config"]}, {"surface", s.to_json()}, {"summary", c->result.summary}};
  }
  md << "\n![classical](surfaces/classical_difference.png)\n\n![rbf](surfaces/rbf_difference.png)\n\n"
     << "## Criterion of fit (cf. Table 5.4)\n\n"
     << "Both compensations, and the raw gyros for scale, through the same strapdown INS as the error-free reference "
     << "(thesis fig 5.3); flights from " << cell(o.start_temp_c) << " C, rates clipped to +-100 deg/s, noise off. "
     << "Short and medium flights are scored at their end, the long one after 1 h (s5.3.3); metres.\n\n"
     << "| flight | duration (s) | uncompensated | classical | RBF | classical / RBF |\n|---|---|---|---|---|---|\n";
  for (const auto& s : scores) {
    const double c = score_m(s.classical), r = score_m(s.rbf);
    md << "| " << s.flight << " | " << cell(s.duration_s) << " | " << cell(score_m(s.none)) << " | " << cell(c) << " | "
       << cell(r) << " | " << cell(c / r) << " |\n";
    summary["criterion_of_fit"][s.flight] = {{"uncompensated", s.none}, {"classical", s.classical}, {"rbf", s.rbf}, {"ratio", c / r}};
  }
  md << "\n";
  for (const auto& s : scores) md << "![" << s.flight << "](cof/" << s.flight << "_error_growth.png)\n";
  md << "\nPer-run outputs (cof.json, ground track, error growth) under `cof/<flight>/<model>/`.\n\n"
     << "## Monte Carlo on the short flight (cf. s5.5, fig 5.18)\n\n"
     << "New sensor noise every run; runs until the Anderson-Darling test accepts normality of every error component "
     << "at 95 % (at least 25). The reference rows are the thesis's: white noise alone, and a bias equal to the noise's "
     << "1-Hz sigma, neither compensated.\n\n"
     << "| compensation | runs | normal | mean (m) | sigma (m) | sigma increase over noise alone (m) |\n|---|---|---|---|---|---|\n";
  for (const Calibrated* c : {&classical, &rbf}) {
    const auto& m = mc[c->label];
    md << "| " << c->label << " | " << m["runs"].get<int>() << " | " << (m["anderson_darling_accepted"].get<bool>() ? "yes" : "no")
       << " | " << cell(m["mean_m"].get<double>()) << " | " << cell(m["sigma_m"].get<double>()) << " | "
       << cell(m.value("sigma_increase_m", 0.0)) << " |\n";
  }
  if (mc["rbf"].contains("reference_just_noise")) {
    const auto& n = mc["rbf"]["reference_just_noise"];
    md << "| just noise | " << n["runs"].get<int>() << " | " << (n["anderson_darling_accepted"].get<bool>() ? "yes" : "no") << " | "
       << cell(n["mean_m"].get<double>()) << " | " << cell(n["sigma_m"].get<double>()) << " | |\n"
       << "| bias " << cell(mc["rbf"]["reference_bias"]["bias_dph"].get<double>()) << " deg/h | 1 | | "
       << cell(mc["rbf"]["reference_bias"]["end_error_m"].get<double>()) << " | | |\n";
  }
  md << "\n![Monte Carlo, RBF](cof/short_monte_carlo/rbf/monte_carlo.png)\n\n"
     << "## Noise (static run, " << describe(still) << ")\n\n"
     << "| term | fitted | unit |\n|---|---|---|\n"
     << "| angle random walk N | " << format_significant(allan.fit.angle_random_walk / 60.0) << " | deg/sqrt(h) |\n"
     << "| bias instability B | " << format_significant(allan.fit.bias_instability) << " | deg/h |\n"
     << "| rate random walk K | " << format_significant(allan.fit.rate_random_walk * 60.0) << " | (deg/h)/sqrt(h) |\n"
     << "| quantization Q | " << format_significant(allan.fit.quantization) << " | arcsec |\n"
     << "| rate ramp R | " << format_significant(allan.fit.rate_ramp * 3600.0) << " | (deg/h)/h |\n\n"
     << "![Allan deviation](allan/allan.png)\n";
  write_file_atomic(dir / "summary.json", summary.dump(2) + "\n");
  write_file_atomic(dir / "report.md", md.str());
  std::cout << "main job done in " << format_number(std::round(seconds * 10) / 10) << " s; report: " << (dir / "report.md").string() << "\n";
}

}  // namespace

void register_run(CLI::App& app, Action& action) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "The main job: simulate, calibrate (classical and RBF), score by the criterion of fit, report");
  cmd->add_option("--out", o->out, "Report directory")->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Sensor config (one gyro; all three INS gyros follow it)")->capture_default_str();
  cmd->add_option("--trajectory", o->trajectory, "RBF calibration trajectory")->capture_default_str();
  cmd->add_option("--soak", o->soak, "Classical calibration trajectory")->capture_default_str();
  cmd->add_option("--static-trajectory", o->static_trajectory, "Static run for the noise analysis")->capture_default_str();
  cmd->add_option("--classical-config", o->classical_config, "Classical calibration config")->capture_default_str();
  cmd->add_option("--rbf-config", o->rbf_config, "RBF calibration config (default builtin:calibration/rbf_noise_free.yaml, "
                                                 "or rbf_noisy.yaml with --noisy)");
  cmd->add_option("--flights", o->flights, "Flights for the criterion of fit: short, medium, long or flight files")->capture_default_str();
  cmd->add_option("--start-temp-c", o->start_temp_c, "Air temperature at the start of every flight")->capture_default_str();
  cmd->add_flag("--noisy", o->noisy, "Calibrate on recordings with the sensor's noise (default: noise-free, as Table 5.4)");
  cmd->add_option("--seed", o->seed, "Seed of every random stream")->capture_default_str();
  cmd->footer("Takes about a minute on two cores. The report folder holds report.md, summary.json, the recordings,\n"
              "the models (usable with gyrosid compensate / cof / export) and every plot.");
  cmd->callback([o, &action] { action = [o] { run_main(*o); }; });
}

}  // namespace gyrosid::cli
