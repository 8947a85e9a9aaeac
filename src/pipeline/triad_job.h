// `gyrosid calibrate --model triad`'s job, called by the command and by Python: the triad model
// (model/triad_model.h) fitted to a triad recording (solvers/triad/triad_fit.h) and its model file - the
// model's values with its sigmas and observability beside them (report/triad_json.h).
#pragma once

#include <nlohmann/json.hpp>

#include "core/recording.h"
#include "solvers/common/options.h"
#include "solvers/triad/triad_fit.h"

namespace gyrosid {

struct TriadCalibration {
  TriadFitOptions options;  // as applied and validated
  TriadFit fit;
  nlohmann::json file;      // what the command writes; training: recording, samples, the options given
};

// `options` are the triad's --set keys (surfaces, estimation, solver, nls.*, surface.*); an unknown key or a bad
// value is an Error naming it.
TriadCalibration calibrate_triad(const Recording& recording, const OptionMap& options);

}  // namespace gyrosid
