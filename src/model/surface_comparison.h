// Estimated against true error surface over a dense (T, omega) grid (thesis Tables 5.2/5.3, figs 5.6-5.8).
//
// At true rate w and steady temperature T the sensor measures w_m = forward(w); the true error is w_m - w,
// the model's estimate its prediction at (w_m, T) (other inputs: temperature rate 0, specific force 1 g
// along the input axis). Differences are reported in deg/h.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "model/calibration_model.h"
#include "sensor/gyro_sensor.h"

namespace gyrosid {

struct SurfaceGridSpec {
  double temp_min_c = -20, temp_max_c = 60;
  double rate_min_dps = -100, rate_max_dps = 100;
  int temp_points = 81, rate_points = 101;
  std::string validate() const;
};

struct SurfaceStats {
  double mean_dph = 0, sigma_dph = 0, max_dph = 0, min_dph = 0, rms_dph = 0;
  nlohmann::json to_json() const;
};

struct SurfaceComparison {
  std::vector<double> temps_c, rates_dps;       // grid axes (rates: true rate)
  Eigen::MatrixXd true_dph, estimated_dph;      // temps x rates
  Eigen::MatrixXd difference_dph() const { return estimated_dph - true_dph; }
  SurfaceStats stats;
};

SurfaceComparison compare_surfaces(const CalibrationModel& model, const GyroSensor& truth, const SurfaceGridSpec& grid);
SurfaceStats surface_stats(const Eigen::MatrixXd& difference_dph);

// The (T, omega) grid on which to compare models with the truth: the sensor's surface grid, narrowed to
// the temperatures every given model was trained on (the training.domain.temperature of their model
// files), so that no model is scored where it would extrapolate.
SurfaceGridSpec comparison_grid(const GyroSensor& truth, const std::vector<nlohmann::json>& trainings);

}  // namespace gyrosid
