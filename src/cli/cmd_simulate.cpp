// gyrosid simulate: a sensor along a calibration trajectory -> recording (+ optional plots).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "core/error.h"
#include "core/recording.h"
#include "report/plots.h"
#include "sensor/error_surface.h"
#include "sim/simulate.h"

namespace gyrosid::cli {
namespace {

struct SimulateOptions {
  std::string sensor = kDefaultSensor;
  std::string trajectory = kDefaultTrajectory;
  std::uint64_t seed = 1;
  std::string out;
  std::size_t samples = 0;
  std::string plots;
  bool noise_free = false;
};

void run_simulate(const SimulateOptions& o) {
  const Simulation sim = simulate_files(o.sensor, o.trajectory, o.seed, o.samples > 0 ? std::optional(o.samples) : std::nullopt, o.noise_free);
  write_recording(sim.recording, o.out);
  std::cout << "wrote " << o.out << ": " << describe(sim) << "\n";
  if (!o.plots.empty()) {
    const std::filesystem::path dir = o.plots;
    const GyroSensor& gyro = representative_gyro(sim.sensor);
    plot_surface(dir / "error_surface.png", error_surface_dps(gyro), kPlotSurfaceGrid,
                 "True rate error of '" + gyro.name + "' (steady temperature)", "rate error (deg/s)");
    const auto& temp = sim.recording.column("temp_c");
    const auto& rate = sim.recording.column(sim.recording.kind() == RecordingKind::single ? "ref_rate_dps" : "ref_rate_z_dps");
    plot_coverage(dir / "coverage.png", temp, rate,
                  "Samples of " + sim.trajectory.profile.name + " over (T, omega)");
    std::cout << "wrote " << (dir / "error_surface.png").string() << ", " << (dir / "coverage.png").string() << "\n";
  }
}

}  // namespace

void register_simulate(CLI::App& app, Action& action) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Simulate a gyro or triad along a rate-table/chamber trajectory and write a recording");
  cmd->add_option("--sensor", o->sensor, "Sensor config (YAML; kind gyro or triad)")->capture_default_str();
  cmd->add_option("--trajectory", o->trajectory, "Calibration trajectory config (YAML)")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of every random stream (same seed, same output, bit for bit)")
      ->capture_default_str();
  cmd->add_option("--samples", o->samples, "Override the trajectory's sampling with N evenly spaced samples");
  cmd->add_flag("--noise-free", o->noise_free, "Deterministic errors only: no random drift, no quantization");
  cmd->add_option("--plots", o->plots, "Also write error_surface.png and coverage.png into this directory");
  cmd->add_option("--out", o->out, "Recording to write (gyrosid-recording/1 CSV)")->required();
  cmd->footer(
      "Examples:\n"
      "  gyrosid simulate --sensor configs/sensors/open_loop_fog.yaml \\\n"
      "      --trajectory configs/trajectories/dual_scan.yaml --seed 1 --out rec.csv\n"
      "  gyrosid simulate --trajectory builtin:trajectories/dual_scan.yaml --samples 1000 --out rec1000.csv\n"
      "A triad sensor config (kind: triad) writes the triad columns. Built-in configs: builtin:sensors/...,\n"
      "builtin:trajectories/... (copies of configs/ in the source tree).");
  cmd->callback([o, &action] { action = [o] { run_simulate(*o); }; });
}

}  // namespace gyrosid::cli
