// gyrosid run: the main job on the built-in default configuration (simulated reference sensor, no outside
// data): simulate the reference FOG along the thesis's dual scan, plot its true error surface and the
// trajectory's coverage, characterise its noise on a static run (Allan deviation), and write a report.
#include <chrono>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/app.h"
#include "cli/common.h"
#include "core/atomic_file.h"
#include "core/format.h"
#include "core/error.h"
#include "core/units.h"
#include "report/plots.h"
#include "sim/simulate.h"

namespace gyrosid::cli {
namespace {

struct RunOptions {
  std::string out = "report";
  std::string sensor = kDefaultSensor;
  std::string trajectory = kDefaultTrajectory;
  std::string static_trajectory = kStaticTrajectory;
  std::uint64_t seed = 1;
};

void step(int index, int total, const std::string& what) {
  std::cerr << "[" << index << "/" << total << "] " << what << std::endl;
}

void run_main(const RunOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path dir = o.out;
  const int steps = 4;

  step(1, steps, "simulating the sensor along the calibration trajectory");
  const Simulation sim = simulate_files(o.sensor, o.trajectory, o.seed);
  write_recording(sim.recording, dir / "recording.csv");

  step(2, steps, "plotting the true error surface and the trajectory coverage");
  const GyroSensor& gyro = representative_gyro(sim.sensor);
  plot_surface(dir / "error_surface.png", error_surface_dps(gyro), SurfaceGrid{},
               "True rate error of '" + gyro.name + "' (steady temperature)", "rate error (deg/s)");
  const bool single = sim.recording.kind() == RecordingKind::single;
  plot_coverage(dir / "coverage.png", sim.recording.column("temp_c"),
                sim.recording.column(single ? "ref_rate_dps" : "ref_rate_z_dps"),
                "Samples of " + sim.trajectory.profile.name + " over (T, omega)");

  step(3, steps, "simulating a static run and computing its Allan deviation");
  const Simulation still = simulate_files(o.sensor, o.static_trajectory, o.seed);
  std::vector<double> noise = rate_column_dph(still.recording, single ? "gyro_dps" : "gyro_z_dps");
  const std::vector<double> ref = rate_column_dph(still.recording, single ? "ref_rate_dps" : "ref_rate_z_dps");
  for (std::size_t i = 0; i < noise.size(); ++i) noise[i] -= ref[i];
  const double dt = uniform_sample_interval(still.recording, "the Allan deviation");
  const AllanReport allan = write_allan(dir / "allan", noise, dt, AllanOptions{},
                                        "Allan deviation of the static run (gyro - reference)",
                                        {{"recording", "simulated static run"}, {"unit", "deg/h"}});

  step(4, steps, "writing the report");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream md;
  md << "# gyrosid main job\n\n"
     << "Built-in default configuration: sensor `" << o.sensor << "`, trajectory `" << o.trajectory
     << "`, seed " << o.seed << ". Run time " << format_number(std::round(seconds * 10) / 10) << " s.\n\n"
     << "## Simulation\n\n" << describe(sim) << ".\n\n"
     << "- `recording.csv`: the simulated recording (gyrosid-recording/1).\n"
     << "- `error_surface.png`: the sensor's true rate error over (T, omega), cf. thesis fig 3.12.\n"
     << "- `coverage.png`: where the trajectory's samples fall in (T, omega), cf. thesis figs 4.6/4.9.\n\n"
     << "![error surface](error_surface.png)\n\n![coverage](coverage.png)\n\n"
     << "## Noise (static run, " << describe(still) << ")\n\n"
     << "| term | fitted | unit |\n|---|---|---|\n"
     << "| angle random walk N | " << format_significant(allan.fit.angle_random_walk / 60.0) << " | deg/sqrt(h) |\n"
     << "| bias instability B | " << format_significant(allan.fit.bias_instability) << " | deg/h |\n"
     << "| rate random walk K | " << format_significant(allan.fit.rate_random_walk * 60.0) << " | (deg/h)/sqrt(h) |\n"
     << "| quantization Q | " << format_significant(allan.fit.quantization) << " | arcsec |\n"
     << "| rate ramp R | " << format_significant(allan.fit.rate_ramp * 3600.0) << " | (deg/h)/h |\n\n"
     << "![Allan deviation](allan/allan.png)\n";
  write_file_atomic(dir / "report.md", md.str());
  std::cout << "main job done in " << format_number(std::round(seconds * 10) / 10) << " s; report: "
            << (dir / "report.md").string() << "\n";
}

}  // namespace

void register_run(CLI::App& app, Action& action) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "The main job on the built-in default configuration; writes a report");
  cmd->add_option("--out", o->out, "Report directory")->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Sensor config")->capture_default_str();
  cmd->add_option("--trajectory", o->trajectory, "Calibration trajectory config")->capture_default_str();
  cmd->add_option("--static-trajectory", o->static_trajectory, "Static run for the noise analysis")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of every random stream")->capture_default_str();
  cmd->callback([o, &action] { action = [o] { run_main(*o); }; });
}

}  // namespace gyrosid::cli
