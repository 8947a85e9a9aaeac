// The main job of `gyrosid run`, callable in-process (experiments, tests, bindings): the thesis's pipeline
// end to end (du Plessis 2013, ch. 5) on a sensor config:
//   1. simulate the sensor on the classical soak (Table 2.1 positions at 20 C plateaus, s5.3.2) and on the
//      dual scan (s4.3), noise-free as the thesis's Table 5.4 unless `noisy`;
//   2. plot the true error surface and the dual scan's coverage; characterise the noise on a static run;
//   3. calibrate the classical model on the soak and the RBF network on the dual scan;
//   4. compare both with the true surface (Tables 5.2/5.3) and score both by the criterion of fit on the
//      flights (Table 5.4), with a Monte Carlo on the short flight (s5.5);
//   5. write report.md and index.html (tables, plots, provenance) and summary.json into `out`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/builtin_configs.h"
#include "model/surface_comparison.h"
#include "nav/cof_report.h"
#include "report/allan_report.h"
#include "solvers/calibrate.h"

namespace gyrosid {

struct MainJobOptions {
  std::filesystem::path out = "report";
  std::string sensor = kDefaultSensor;
  std::string trajectory = kDefaultTrajectory;  // the RBF's calibration trajectory
  std::string soak = "builtin:trajectories/classical_soak.yaml";   // the classical model's
  std::string static_trajectory = kStaticTrajectory;
  std::string classical_config = "builtin:calibration/classical.yaml";
  std::string rbf_config;  // empty: rbf_noise_free.yaml, or rbf_noisy.yaml when noisy
  std::vector<std::string> flights = {"short", "medium", "long"};
  double start_temp_c = 10.0;
  bool noisy = false;      // calibrate on recordings with the sensor's noise
  std::uint64_t seed = 1;
  // Called as each of the job's steps starts (default: "[i/n] what" on stderr).
  std::function<void(int step, int steps, const std::string& what)> on_step;

  std::string validate() const;
  std::string rbf_config_used() const;
};

// A model calibrated by the job and compared with the true surface.
struct CalibratedModel {
  std::string label;   // classical | rbf
  std::string config;  // calibration config it was fitted with
  CalibrationResult result;
  SurfaceComparison surface;
};

// One flight's criterion of fit for both models (paths dropped once their plots are written).
struct FlightScores {
  std::string flight;
  nav::CofReport classical, rbf;  // rbf.uncompensated is the raw gyros' run
};

struct MainJobResult {
  std::string dual_description, soak_description, static_description;
  AllanReport allan;  // of the static run, deg/h
  CalibratedModel classical, rbf;
  std::vector<FlightScores> flights;
  std::vector<nav::CofReport> short_monte_carlo;  // classical, rbf
  double run_time_s = 0.0;
};

// Runs the job and writes its outputs under options.out; Error (naming the option) for a bad request.
MainJobResult run_main_job(const MainJobOptions& options);

// report.md, index.html (the same content with the plots inline) and summary.json of a finished job.
void write_main_job_report(const MainJobOptions& options, const MainJobResult& result);

}  // namespace gyrosid
