// gyrosid cof: score a calibration by the strapdown-INS position error it leaves (thesis s4.5, fig 5.3).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "nav/cof_report.h"
#include "report/cof_plots.h"

namespace gyrosid::cli {
namespace {

struct CofCommand {
  nav::CofRequest request;
  std::string monte_carlo;
  std::string out;
  double clip = 100.0;
  std::string probe = "coil";
  bool resume = false;
};

void run_cof(CofCommand c) {
  if (!c.monte_carlo.empty()) {
    c.request.monte_carlo = true;
    if (c.monte_carlo == "auto") {
      c.request.mc.runs = 0;
    } else {
      char* end = nullptr;
      const long n = std::strtol(c.monte_carlo.c_str(), &end, 10);
      if (*end != '\0' || n < 8) fail("--monte-carlo: expected auto or a number of runs >= 8, got '", c.monte_carlo, "'");
      c.request.mc.runs = static_cast<int>(n);
    }
  }
  c.request.options.clip_rate_dps = c.clip;
  c.request.options.probe = parse_enum<nav::TemperatureProbe>(c.probe, "--temperature-probe");
  // A Monte Carlo saves its finished runs as it goes; --resume continues a killed run to the same result.
  if (c.request.monte_carlo) c.request.checkpoint = std::filesystem::path(c.out) / ".cof_checkpoint.json";
  c.request.resume = c.resume;
  if (c.resume) remove_stale_temporaries(c.out);
  const nav::CofReport r = nav::evaluate_criterion_of_fit(c.request);
  write_cof_outputs(r, c.out);
  if (!c.request.checkpoint.empty()) std::filesystem::remove(c.request.checkpoint);
  std::cout << "criterion of fit, " << r.request.trajectory << " (" << format_significant(r.duration_s(), 4)
            << " s): end error " << format_significant(r.run.end_error_m, 4) << " m (along "
            << format_significant(r.decomposed.x(), 3) << ", cross " << format_significant(r.decomposed.y(), 3)
            << ", " << format_significant(r.decomposed.z(), 3) << " m); uncompensated "
            << format_significant(r.uncompensated.end_error_m, 4) << " m; drift "
            << format_significant(r.drift_m_per_h, 4) << " m/h";
  if (r.mc) {
    std::cout << "; Monte Carlo " << r.mc->runs << " runs: mean " << format_significant(r.mc->mean_m, 4) << " m, sigma "
              << format_significant(r.mc->sigma_m, 4) << " m" << (r.mc->normal ? "" : " (normality not reached)");
  }
  std::cout << "\nwrote " << c.out << "/cof.json and plots\n";
}

}  // namespace

void register_cof(CLI::App& app, Action& action) {
  auto c = std::make_shared<CofCommand>();
  c->request.sensor = kDefaultSensor;
  CLI::App* cmd = app.add_subcommand("cof", "Criterion of fit: position error a calibration leaves in a strapdown INS");
  cmd->add_option("--model", c->request.model, "Model file, 'none' (raw gyro) or 'truth' (perfect compensation)")->required();
  cmd->add_option("--sensor", c->request.sensor, "Sensor perturbing all three gyros (a gyro config is used on each axis)")->capture_default_str();
  cmd->add_option("--trajectory", c->request.trajectory, "short, medium, long, a flight .yaml or a flight .csv")->capture_default_str();
  cmd->add_option("--rate-hz", c->request.rate_hz, "IMU rate for generated flights")->capture_default_str();
  cmd->add_option("--start-temp-c", c->request.options.start_temp_c, "Air temperature at the start (thesis: 10 C)")->capture_default_str();
  cmd->add_option("--thermal-delay-s", c->request.options.thermal_delay_s, "Coil temperature delay behind the air (thesis: 300 s)")->capture_default_str();
  cmd->add_option("--temperature-probe", c->probe, "Temperature given to the model: coil (the gyro's probe, thesis) or air")->capture_default_str();
  cmd->add_option("--rate-limit-dps", c->clip, "Clip gyro rates to this range (thesis: 100; 0: no limit)")->capture_default_str();
  cmd->add_flag("--scale-rates", c->request.options.scale_rates, "Scale the rates into the range instead of clipping");
  cmd->add_option("--monte-carlo", c->monte_carlo, "auto (until Anderson-Darling accepts normality, >= 25 runs) or a number of runs");
  cmd->add_option("--max-runs", c->request.mc.max_runs, "Run cap of --monte-carlo auto")->capture_default_str();
  cmd->add_option("--seed", c->request.seed, "Seed of the noise streams")->capture_default_str();
  cmd->add_flag("--resume", c->resume, "Continue a killed Monte Carlo from its checkpoint in --out (same inputs and seed; "
                                       "the result equals an uninterrupted run's)");
  cmd->add_option("--out", c->out, "Output directory: cof.json, ground_track.png, error_growth.png, monte_carlo.png")->required();
  cmd->footer(
      "The reference IMU data and the same data with the three gyros perturbed by the sensor model and compensated\n"
      "by the model go through the same WGS-84 strapdown INS; the end-of-trajectory position difference is the\n"
      "criterion (fig 5.3), split into along-track and two cross-track components (fig 5.19). Without\n"
      "--monte-carlo the sensor's noise is off (the thesis's noise-free Table 5.4).\n"
      "Example: gyrosid cof --model rbf.json --trajectory short --monte-carlo auto --out cof_short/");
  cmd->callback([c, &action] { action = [c] { run_cof(*c); }; });
}

}  // namespace gyrosid::cli
