// What block means (core/decimation.h) can do to a fitted model: a model f nonlinear in an input that varies
// inside a block sees the block's mean input, while the block's mean output is the mean of f over the block -
// larger or smaller by about f'' var / 2. Measured on the fitted model at every block with the two-point rule
// that matches each input's within-block variance s_k^2:
//
//   bias = sum_k ( f(x + s_k e_k) + f(x - s_k e_k) ) / 2 - f(x)  =  sum_k f_kk s_k^2 / 2 + O(s^4),
//
// inputs taken one at a time (their within-block covariance left out: over a block of a fraction of a second
// the temperature barely moves while the rate does).
#pragma once

#include <string>
#include <vector>

#include "core/decimation.h"
#include "model/calibration_model.h"

namespace gyrosid {

// A feature of the model and the recording column whose within-block spread it has, with the factor from the
// column's unit to the feature's (deg/s -> rad/s for measured_rate, 1 for temperature).
struct SpreadInput {
  std::string feature, column;
  double scale = 1.0;
};

// The spreads of a single-gyro model's inputs: measured_rate from ref_rate_dps (its deterministic part moves
// with the table), temperature from temp_c.
std::vector<SpreadInput> gyro_spread_inputs();

// The largest |bias| over the blocks (rad/s); 0 when nothing was averaged or no input varies.
double largest_averaging_bias(const CalibrationModel& model, const Dataset& data, const Decimation& decimation,
                              const std::vector<SpreadInput>& inputs);

}  // namespace gyrosid
