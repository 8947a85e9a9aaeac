// `gyrosid surface` as a library job: a model's estimated error surface against the sensor's true one on a
// (T, omega) grid (thesis Tables 5.2/5.3, figs 5.6-5.8). The CLI parses, this job computes, and
// report/surface_report.h writes surface.json, surface.csv and the plots.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "core/builtin_configs.h"
#include "model/calibration_model.h"
#include "model/surface_comparison.h"

namespace gyrosid {

struct SurfaceJobInput {
  std::string model;                               // model file written by calibrate
  std::string sensor = kDefaultSensor;             // sensor config holding the true error model
  std::optional<std::array<double, 2>> temp_range_c;    // default: the training temperatures within the sensor's grid
  std::optional<std::array<double, 2>> rate_range_dps;  // default: -100, 100
  std::optional<std::array<int, 2>> points;             // temperatures, rates; default 81, 101
  std::string validate() const;
};

struct SurfaceJobResult {
  std::unique_ptr<CalibrationModel> model;
  SurfaceGridSpec grid;
  SurfaceComparison comparison;
};

// Error naming the option or file for a bad request.
SurfaceJobResult run_surface_job(const SurfaceJobInput& input);

}  // namespace gyrosid
