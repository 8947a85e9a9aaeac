// The simulation a recording is explained against, and the structure whose coefficients are re-estimated:
// a saved model, the baseline family fitted on a calibration recording, or the baseline family itself.
#pragma once

#include <memory>
#include <string>

#include "explain/baseline.h"
#include "explain/effect.h"
#include "explain/explain_input.h"
#include "model/calibration_model.h"

namespace gyrosid::explain {

struct Simulation {
  ModelSpec base;                            // the terms re-estimated (a prior's prediction is one of them)
  std::unique_ptr<CalibrationModel> prior;   // the fixed model, if any
  std::string description;
};

// The name of the channel that carries a prior model's prediction inside the base's terms.
inline constexpr const char* kPriorChannel = "__prior";

// The baseline family's form for `form`: surface or polynomial as given; for automatic, the surface when its
// BIC on the training rows (least squares on the error, beside a polynomial in time) is lower than the
// polynomial's, with *why one sentence of the comparison. A surface of ~100 columns must earn its place over a
// polynomial of 16: where it need not, it only absorbs physics the candidates would test (a scale-factor
// asymmetry, issue 34 class 5).
BaselineForm choose_baseline_form(BaselineForm form, const ExplainInput& in, std::string* why);

// From --model, --baseline or neither. A prior's prediction (deg/h) goes into in.signals as kPriorChannel
// and is a term of the base (its gain re-estimated).
Simulation make_simulation(ExplainInput& in, const std::string& model_path, const std::string& baseline_path, BaselineForm form,
                           const InputOptions& input_options);

// A model's inputs along the explained gyro, with the reference rate in place of the measured one: a
// prediction from the noisy output would carry the noise (times the scale factor), and a free gain on it
// would fit noise.
Dataset dataset_of(const ExplainInput& in, const std::vector<std::string>& features);

}  // namespace gyrosid::explain
