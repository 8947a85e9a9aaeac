// gyrosid run: the main job (pipeline/main_job.h) with its options from the command line.
#include <cmath>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/format.h"
#include "pipeline/main_job.h"

namespace gyrosid::cli {

void register_run(CLI::App& app, Action& action) {
  auto o = std::make_shared<MainJobOptions>();
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
  cmd->callback([o, &action] {
    action = [o] {
      const MainJobResult r = run_main_job(*o);
      std::cout << "main job done in " << format_number(std::round(r.run_time_s * 10) / 10) << " s; report: "
                << (o->out / "report.md").string() << "\n";
    };
  });
}

}  // namespace gyrosid::cli
