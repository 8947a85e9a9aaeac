// gyrosid explain: when a simulation and a recording differ, find which physics the simulation left out,
// model it and show the fit improve on held-out data.
//
//   1. the simulation: a saved model (--model), the baseline family fitted on a calibration recording
//      (--baseline), or the baseline family fitted on this recording's training blocks; its existing
//      coefficients are always re-estimated, so a mis-set coefficient is never reported as missing physics
//      (simulation.h);
//   2. candidates from the effect library (effect.h), projected off what the simulation can absorb,
//      selected forward by BIC with block-bootstrap p-values and Holm's correction (selection.h);
//   3. every selected effect must survive leave-one-block-out refits (stability) and must not make the
//      held-out blocks worse (judge.h) - held-out samples where the simulation or the model judged
//      extrapolates excluded (heldout_support.h); one the held-out blocks cannot test needs dBIC >= ambiguity_bic against the
//      coloured noise re-estimated with it; the model is refitted jointly in Ceres with confidence
//      intervals (refit.h);
//   4. the residual is diagnosed before and after (diagnostics.h); significant structure no effect
//      explains is reported as unexplained and localised in time, in (T, omega) and by channel.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "core/checkpoint.h"
#include "core/decimation.h"
#include "core/recording.h"
#include "explain/baseline.h"
#include "explain/explain_input.h"
#include "explain/explain_result.h"
#include "explain/support_check.h"
#include "model/explained_model.h"

namespace gyrosid::explain {

struct ExplainOptions {
  std::string model_path;     // the simulation as a saved model
  std::string baseline_path;  // or a calibration recording to fit the baseline family on
  std::string effects;        // restrict the library: comma-separated effect ids (empty: all)
  BaselineForm baseline_form = BaselineForm::automatic;
  InputOptions input;
  SelectionOptions selection;
  double min_stability = 0.5; // fraction of leave-one-block-out refits in which an effect must keep dBIC > 0
  // Held-out samples whose leverage under the training fit of the simulation or of a model judged exceeds this
  // multiple of the mean training leverage are outside the training support (heldout_support.h) and confirm nothing.
  double heldout_leverage = 10.0;
  // An effect the held-out blocks do not hold (confined to part of the record) is checked on its own support.
  SupportCheckOptions support_check;
  std::string validate() const;
};

struct ExplainResult {
  ExplainSummary summary;                   // explain.json (report/explain_json.h)
  std::unique_ptr<ExplainedModel> model;    // the refitted model
  ExplainInput input;
  Eigen::VectorXd simulation_residual_dph;  // recording - simulation as given (before re-estimation)
  Eigen::VectorXd residual_before_dph;      // with the simulation's coefficients re-estimated
  Eigen::VectorXd residual_after_dph;       // with the effects added
};

// With a checkpoint (not owned), every finished selection step's bootstrap is saved there and, on resume,
// taken from it: the result equals an uninterrupted run's. With `decimation` (the recording is block means,
// core/decimation.h), the summary states it and the refitted model's averaging bias
// (model/averaging_bias.h).
ExplainResult explain_recording(const Recording& recording, const ExplainOptions& options, Checkpoint* checkpoint = nullptr,
                                const Decimation* decimation = nullptr);

// The inputs whose within-block spread a decimated explain states: the explained gyro's reference rate and
// temperature columns in a recording with these columns.
std::vector<std::string> explain_spread_columns(const std::vector<std::string>& names, const std::string& axis);

}  // namespace gyrosid::explain
