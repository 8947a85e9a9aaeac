// `gyrosid calibrate` as a library job (issue 31): the CLI and Python call it. With a request it fits that kind,
// a single gyro's or the triad's; without one it characterises the recording's noise and chooses the preset for
// it (solvers/preset_choice.h), reading the recording as block means when that pays (core/decimation.h, auto).
// Writing the model file is the caller's (save_model(path, *fit.model, fit.extra)).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "core/decimation.h"
#include "core/recording.h"
#include "model/fit_notes.h"
#include "solvers/calibrate.h"
#include "solvers/preset_choice.h"

namespace gyrosid {

struct CalibrateJobInput {
  std::optional<CalibrationRequest> request;  // none: the preset chosen from the recording's noise
  std::string decimate;                       // none | auto | N; empty: auto when the preset is chosen, else none
  std::function<void(const std::string&)> on_step;  // "calibrate: fitting the rbf model to 3000 samples"
};

struct CalibrateJobResult {
  ModelFit fit;                    // its extra's training holds the preset chosen, its summary the decimation
  std::optional<PresetChoice> choice;
  Decimation decimation;           // what was read (factor 1: the recording as it is)
  std::string averaging_statement; // the decimated fit's averaging bias (state_decimation); empty when not decimated
  FitNotes notes;
};

// From a recording file: the single gyro, or with `axis` (x, y, z) one gyro of a triad recording under the
// single-gyro names, only the columns the fit needs read; a kind of several gyros (the triad) reads the whole
// recording and takes neither `axis` nor `decimate`. Error naming the file, column or option.
CalibrateJobResult run_calibrate_job(const std::string& recording, const std::string& axis, const CalibrateJobInput& input);
// From a recording in memory.
CalibrateJobResult run_calibrate_job(const Recording& recording, const CalibrateJobInput& input);

}  // namespace gyrosid
