// Estimated against true error surface over a dense (T, omega) grid (thesis Tables 5.2/5.3, figs 5.6-5.8).
//
// At true rate w and steady temperature T the sensor measures w_m = forward(w); the true error is w_m - w,
// the model's estimate its prediction at (w_m, T) (other inputs: temperature rate 0, specific force 1 g
// along the input axis). Differences are reported in deg/h.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "model/calibration_model.h"
#include "sensor/gyro_sensor.h"

namespace gyrosid {

// A (T, omega) grid, evenly spaced, ends included: the comparisons' (81 x 101) and the plots' (plots.h).
struct SurfaceGridSpec {
  double temp_min_c = -20, temp_max_c = 60;
  double rate_min_dps = -100, rate_max_dps = 100;
  int temp_points = 81, rate_points = 101;
  std::string validate() const;
  std::vector<double> temperatures_c() const;
  std::vector<double> rates_dps() const;
};

struct SurfaceStats {
  double mean_dph = 0, sigma_dph = 0, max_dph = 0, min_dph = 0, rms_dph = 0;
  nlohmann::json to_json() const;
};

// The predictive sigma of a model with a posterior (CalibrationModel::predict_with_sigma) over the grid, and
// how well it describes the actual error: rms sigma, and the fraction of grid points whose |estimated -
// true| lies inside the 95 % band (1.96 sigma).
struct SigmaStats {
  double rms_sigma_dph = 0, max_sigma_dph = 0, coverage_95 = 0;
  nlohmann::json to_json() const;
};

struct SurfaceComparison {
  std::vector<double> temps_c, rates_dps;       // grid axes (rates: true rate)
  Eigen::MatrixXd true_dph, estimated_dph;      // temps x rates
  Eigen::MatrixXd sigma_dph;                    // temps x rates; empty for a model without a posterior
  Eigen::MatrixXd difference_dph() const { return estimated_dph - true_dph; }
  SurfaceStats stats;
  SigmaStats sigma_stats;                       // when sigma_dph is filled
};

SurfaceComparison compare_surfaces(const CalibrationModel& model, const GyroSensor& truth, const SurfaceGridSpec& grid);

// The predictive sigma of a model with a posterior on a (T, omega) grid without a truth: the measured rate
// is the grid's rate, the other inputs as compare_surfaces sets them. Where it is largest is where the
// training data (or a prior) said least. Error for a model without a posterior.
struct SigmaMap {
  std::vector<double> temps_c, rates_dps;
  Eigen::MatrixXd sigma_dph;  // temps x rates
  double rms_dph = 0, max_dph = 0, max_temp_c = 0, max_rate_dps = 0;
};
SigmaMap predictive_sigma_map(const CalibrationModel& model, std::vector<double> temps_c, std::vector<double> rates_dps);
SurfaceStats surface_stats(const Eigen::MatrixXd& difference_dph);

// The (T, omega) grid on which to compare models with the truth: the sensor's surface grid, narrowed to
// the temperatures every given model was trained on (the training.domain.temperature of their model
// files), so that no model is scored where it would extrapolate.
SurfaceGridSpec comparison_grid(const GyroSensor& truth, const std::vector<nlohmann::json>& trainings);

}  // namespace gyrosid
