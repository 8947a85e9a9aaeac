// Compensation of a whole recording (thesis figs 4.17-4.19): the recording with the model's compensated
// rate added as compensated_dps, and the rms error against the reference before and after where the
// recording has one.
#pragma once

#include <optional>

#include "core/recording.h"
#include "model/calibration_model.h"

namespace gyrosid {

struct CompensatedRecording {
  Recording recording;                  // the input plus compensated_dps
  std::optional<double> rms_before_dph;  // gyro - ref, when ref_rate_dps is recorded everywhere
  std::optional<double> rms_after_dph;   // compensated - ref
};

CompensatedRecording compensate_recording(const CalibrationModel& model, Recording recording);

}  // namespace gyrosid
