// Fitting any calibration model to a recording - what `gyrosid calibrate` does, callable in-process by
// experiments: rbf (with a named solver), classical (s5.3.2) or greybox (the unified sensor model).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/recording.h"
#include "model/calibration_model.h"
#include "model/normalizer.h"
#include "solvers/common/options.h"

namespace gyrosid {

struct CalibrationRequest {
  std::string model = "rbf";  // rbf | classical | greybox
  std::string solver = "ols"; // rbf only
  OptionMap options;          // solver options (rbf) or model options (classical, greybox)
  std::vector<std::string> features;  // empty: the model's defaults
  ModelTarget target = ModelTarget::error;
  NormalizationKind normalization = NormalizationKind::range;
};

struct CalibrationResult {
  std::unique_ptr<CalibrationModel> model;
  nlohmann::json summary;   // termination, iterations, cost history, nodes, time, peak memory, ...
  nlohmann::json training;  // provenance: recording, samples, request
};

CalibrationResult calibrate(const Recording& recording, const CalibrationRequest& request);
std::string model_help(const std::string& model);  // the model's options (classical, greybox)

}  // namespace gyrosid
