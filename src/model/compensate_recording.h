// Compensation of a whole recording (thesis figs 4.17-4.19): the recording with the model's compensated
// rate added as compensated_dps, and the rms error against the reference before and after where the
// recording has one. A model with a posterior also adds compensated_sigma_dps, the predictive sigma of its
// estimate (steady state), and the fraction of samples whose compensated - reference lies inside 1.96 sigma.
#pragma once

#include <filesystem>
#include <string>

#include "core/recording.h"
#include "model/calibration_model.h"
#include "model/sensor_model.h"
#include "model/triad_model.h"

namespace gyrosid {

CompensatedRecording compensate_recording(const CalibrationModel& model, Recording recording);

// The same from file to file, streamed: a chunk of rows read, compensated and written at a time, so memory
// holds one chunk (written atomically: a temporary file renamed at the end). A model that is not pointwise
// (CalibrationModel::pointwise(): a thermal lag, a temperature rate) is first run over the whole recording,
// read with only the columns it needs. `axis` (x, y or z) applies the single-gyro model to that gyro of a
// triad recording: its columns are read as gyro_dps, ref_rate_dps and temp_c, and compensated_<axis>_dps
// (and compensated_sigma_<axis>_dps) are added. The returned recording holds no rows, only the columns written.
CompensatedRecording compensate_file(const CalibrationModel& model, const std::filesystem::path& input, const std::filesystem::path& output,
                                     const std::string& axis = "", std::size_t chunk_rows = 65536);

// A triad model's compensation (TriadModel::compensate_recording and compensate_file, defined in
// compensate_recording.cpp) adds compensated_{x,y,z}_dps, the body rates, and the rms error over the three
// axes against ref_rate_{x,y,z}_dps before and after.

}  // namespace gyrosid
