// The one writer of `gyrosid surface`'s files (pipeline/surface_job.h): surface.json (the grid and the
// statistics of estimated - true, deg/h, as the thesis's Tables 5.2/5.3), surface.csv (every grid point) and
// the plots (true, estimated, difference; the predictive sigma of a model with a posterior; an RBF
// network's nodes on its surface).
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "model/calibration_model.h"
#include "model/surface_comparison.h"

namespace gyrosid {

// surface.json's content; `model_file` and `sensor` as the request named them.
nlohmann::json surface_json(const std::string& model_file, const std::string& sensor, const CalibrationModel& model, const SurfaceGridSpec& grid,
                            const SurfaceComparison& c);
// Writes surface.json, surface.csv and the PNG plots into `dir` (each file atomically).
void write_surface_report(const std::filesystem::path& dir, const nlohmann::json& summary, const CalibrationModel& model, const SurfaceComparison& c);

}  // namespace gyrosid
