// What block means (core/decimation.h) can do to a fitted model: a model f nonlinear in an input that varies
// inside a block sees the block's mean input, while the block's mean output is the mean of f over the block -
// larger or smaller by about f'' var / 2. Measured on the fitted model at every block i with the two-point
// rule, each input k shifted along the whole recording by its largest within-block standard deviation S_k (a
// constant shift: a model that filters an input in time - a thermal lag, a temperature rate - sees a steady
// change, not a jagged one) and scaled to the block's own s_ik:
//
//   bias_i = sum_k (s_ik / S_k)^2 ( f(x + S_k e_k) + f(x - S_k e_k) - 2 f(x) )_i / 2  =  sum_k f_kk s_ik^2 / 2 + O(S^4),
//
// inputs taken one at a time (their within-block covariance left out: over a block of a fraction of a second
// the temperature barely moves while the rate does). The largest biases sit in the few blocks where the
// table switched rate, so the count of blocks above a tenth of the residual rms is stated beside the largest.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/decimation.h"
#include "model/calibration_model.h"

namespace gyrosid {

// A feature of the model and the recording column whose within-block spread it has, with the factor from the
// column's unit to the feature's (deg/s -> rad/s for measured_rate, 1 for temperature).
struct SpreadInput {
  std::string feature, column;
  double scale = 1.0;
};

// The model inputs of the spreads a decimation kept: a reference-rate column (deg/s: its deterministic part is
// what moves the measured rate inside a block) for measured_rate, a temperature column (C) for temperature.
std::vector<SpreadInput> gyro_spread_inputs(const Decimation& decimation);

struct AveragingBias {
  double largest_dph = 0.0;
  double threshold_dph = 0.0;    // a tenth of the residual rms
  std::size_t blocks_over = 0;   // blocks whose |bias| exceeds the threshold
  std::size_t blocks = 0;
  std::string statement() const;
  nlohmann::json to_json() const;
};

// The bias at every block of `data` (the decimated recording's dataset) and its summary; residual_rms_dph:
// the fit's residual rms per block mean.
AveragingBias averaging_bias(const CalibrationModel& model, const Dataset& data, const Decimation& decimation, double residual_rms_dph);

// The decimation with what it does to the fitted model: Decimation::to_json(), "averaging_bias" and one
// "statement" sentence for the command's output and the result summary.
nlohmann::json decimation_summary(const Decimation& decimation, const AveragingBias& bias);

}  // namespace gyrosid
