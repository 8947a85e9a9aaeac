#include "pipeline/calibrate_job.h"

#include <utility>
#include <vector>

#include "core/axis_view.h"
#include "core/error.h"
#include "core/format.h"
#include "core/recording_reader.h"

namespace gyrosid {
namespace {

DecimationRequest decimation_of(const CalibrateJobInput& in) {
  return DecimationRequest::parse(in.decimate.empty() ? (in.request ? "none" : "auto") : in.decimate, "--decimate");
}

void step(const CalibrateJobInput& in, const std::string& what) {
  if (in.on_step) in.on_step(what);
}

// The fit of what was read: the request, or the preset chosen for the recording's noise.
CalibrateJobResult fit_read(const DecimatedRecording& read, const CalibrateJobInput& in) {
  CalibrateJobResult r;
  const Recording& rec = read.recording;
  r.decimation = read.decimation;
  CalibrationRequest request = in.request.value_or(CalibrationRequest{});
  if (!in.request) {
    step(in, "calibrate: characterising the noise to choose the preset");
    r.choice = choose_preset(rec);
    request = r.choice->request;
  }
  step(in, str_cat("calibrate: fitting the ", request.model, " model to ", rec.rows(), " samples"));
  CalibrationResult result = calibrate(rec, request);
  if (r.choice) result.training["preset"] = {{"chosen", r.choice->preset}, {"reasons", r.choice->reasons}};
  if (read.decimation.applied()) r.averaging_statement = state_decimation(result, rec, read.decimation);
  r.notes = fit_notes_of(result.summary.details);
  r.fit = model_fit_of(std::move(result));
  return r;
}

// A kind of several gyros (the triad): the whole recording, at its own rate.
CalibrateJobResult fit_together(const Recording& recording, const std::string& axis, const CalibrateJobInput& in) {
  if (!axis.empty() || !in.decimate.empty()) {
    fail("--axis and --decimate apply to single-gyro models (--model ", in.request->model, " calibrates all the gyros at the recorded rate)");
  }
  step(in, str_cat("calibrate: fitting the ", in.request->model, " model to ", recording.rows(), " samples"));
  CalibrateJobResult r;
  r.fit = fit_model(recording, *in.request);
  r.notes = fit_notes_of(r.fit.summary.details);
  return r;
}

bool several_gyros(const CalibrateJobInput& in) { return in.request && !fits_one_gyro(*in.request); }

}  // namespace

CalibrateJobResult run_calibrate_job(const std::string& path, const std::string& axis, const CalibrateJobInput& in) {
  if (several_gyros(in)) return fit_together(read_recording(path), axis, in);
  const DecimationRequest decimation = decimation_of(in);  // a bad --decimate before the file is read
  const GyroColumns g = gyro_columns(RecordingReader(path).names(), axis, path);
  std::vector<std::string> columns{"t_s", g.gyro, g.ref}, inputs{g.ref};
  if (!g.temp.empty()) columns.push_back(g.temp), inputs.push_back(g.temp);
  for (const auto& f : in.request ? in.request->features : std::vector<std::string>{}) {
    if (f != "measured_rate" && f != "temperature" && f != "temperature_rate") columns.push_back(f);
  }
  DecimatedRecording read = read_decimated(path, decimation, inputs, columns);
  read.recording = single_axis_view(std::move(read.recording), axis);
  return fit_read(read, in);
}

CalibrateJobResult run_calibrate_job(const Recording& recording, const CalibrateJobInput& in) {
  if (several_gyros(in)) return fit_together(recording, "", in);
  std::vector<std::string> inputs{"ref_rate_dps"};
  if (recording.has("temp_c")) inputs.push_back("temp_c");
  return fit_read(decimate(recording, decimation_of(in), inputs), in);
}

}  // namespace gyrosid
