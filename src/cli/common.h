// Helpers shared by the subcommands: default config paths, unit handling of recording columns, the
// error-surface function of a sensor.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/recording.h"
#include "model/surface_comparison.h"
#include "sensor/allan.h"
#include "sensor/sensor_config.h"

namespace gyrosid::cli {

inline constexpr const char* kDefaultSensor = "builtin:sensors/open_loop_fog.yaml";
inline constexpr const char* kDefaultTrajectory = "builtin:trajectories/dual_scan.yaml";
inline constexpr const char* kStaticTrajectory = "builtin:trajectories/static_2h.yaml";

// A rate column in deg/h, whatever its suffix (_dps or _dph); Error for other columns.
std::vector<double> rate_column_dph(const Recording& recording, const std::string& name);

// The deterministic rate error of one gyro at steady temperature on a level table (input axis up,
// specific force 1 g along it), in deg/s: the "true error surface" of thesis fig 3.12.
std::function<double(double temp_c, double rate_dps)> error_surface_dps(const GyroSensor& gyro);
const GyroSensor& representative_gyro(const SensorSpec& sensor);  // the single gyro, or a triad's z gyro

// The (T, omega) grid on which to compare models with the truth: the sensor's surface grid, narrowed to
// the temperatures every given model was trained on (their training.domain.temperature), so that no model
// is scored where it would extrapolate.
SurfaceGridSpec comparison_grid(const GyroSensor& truth, const std::vector<nlohmann::json>& trainings);

struct AllanReport {
  std::vector<AllanPoint> curve;  // deg/h
  AllanCoefficients fit;          // deg/h-based units
};
// Allan analysis of a rate (deg/h) written to dir: allan.csv, allan.json, allan.png.
AllanReport write_allan(const std::filesystem::path& dir, const std::vector<double>& rate_dph, double dt_s,
                        const AllanOptions& options, const std::string& title, nlohmann::json provenance);

}  // namespace gyrosid::cli
