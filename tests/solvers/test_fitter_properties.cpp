// One property suite run over every model kind `calibrate` fits (solvers/calibrate.h's model_fitters()), the
// triad included: its help names it, an unknown option is refused by name before any data is read, and a fit
// (fit_model) to a simulated recording of its kind - a single gyro's dual scan, a triad's rate sweep - is usable,
// removes most of the recorded error, writes a file that loads back through the model kinds' registry to the
// same compensation, and repeats bit for bit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "error_of.h"
#include "model/calibration_model.h"
#include "model/dataset.h"
#include "model/model_kinds.h"
#include "model/sensor_model.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;

// The reference FOG along the thesis's dual scan, 1500 samples: the whole 62-min scan at 0.4 Hz, every
// temperature and rate it visits.
const Recording& dual_scan() {
  static const Recording r = [] {
    TrajectorySpec t = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
    t.sampling = Sampling{1500, 0.0};
    return simulate(load_sensor_file("builtin:sensors/open_loop_fog.yaml"), t, 3).recording;
  }();
  return r;
}

// The reference triad along the rate sweep, 3000 samples: every gyro turned through its rates and temperatures.
// The triad's defaults (M and b(T), no surfaces) leave its surfaces: 21 % of the recorded rms, noise-free 21 % too.
const Recording& triad_sweep() {
  static const Recording r = [] {
    TrajectorySpec t = load_trajectory_file("builtin:trajectories/triad_rate_sweep.yaml");
    t.sampling = Sampling{3000, 0.0};
    return simulate(load_sensor_file("builtin:sensors/fog_triad.yaml"), t, 3).recording;
  }();
  return r;
}

double rms(const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / static_cast<double>(v.size())); }

class ModelFitterProperties : public ::testing::TestWithParam<std::string> {};

TEST_P(ModelFitterProperties, HelpNamesItAndUnknownOptionsAreRefused) {
  EXPECT_THAT(model_fitters().at(GetParam()).help(), ::testing::StartsWith(GetParam() + " - "));
  CalibrationRequest request;
  request.model = GetParam();
  request.options = {{"no_such_option", "1"}};
  EXPECT_THAT(testing_support::error_of([&] { model_fitters().make(GetParam(), request); }),
              ::testing::HasSubstr("unknown option 'no_such_option'"));
}

TEST_P(ModelFitterProperties, FitRemovesTheErrorLoadsBackAndRepeats) {
  CalibrationRequest request;
  request.model = GetParam();
  const Recording& recording = fits_one_gyro(request) ? dual_scan() : triad_sweep();
  const ModelFit a = fit_model(recording, request), b = fit_model(recording, request);
  ASSERT_TRUE(a.summary.usable()) << a.summary.message;
  EXPECT_GE(a.summary.iterations, 1);
  EXPECT_EQ(a.summary.iterations, static_cast<int>(a.summary.cost_history.size()));
  EXPECT_EQ(a.model->gyros(), recording.kind() == RecordingKind::single ? 1 : 3);
  const CompensatedRecording c = a.model->compensate_recording(recording);
  ASSERT_TRUE(c.rms_before_dph && c.rms_after_dph);
  RecordProperty("residual_share_percent", std::to_string(100.0 * *c.rms_after_dph / *c.rms_before_dph));  // per fitter in --gtest_output=xml
  EXPECT_LT(*c.rms_after_dph, 0.25 * *c.rms_before_dph) << "the fit leaves most of the recorded error";
  // Its file loads through the model kinds' registry to the same compensation (to the last bits: the triad's file
  // holds b(T) in deg/h, the model rad/s), and holds the fit's extra.
  const fs::path file = fs::temp_directory_path() / ("gyrosid_fitter_" + GetParam() + ".json");
  save_model(file, *a.model, a.extra);
  const std::unique_ptr<SensorModel> loaded = load_sensor_model(file);
  EXPECT_EQ(loaded->kind(), a.model->kind());
  EXPECT_EQ(load_model_json(file).at("training"), a.extra.at("training"));
  const Recording again = loaded->compensate_recording(recording).recording;
  for (const std::string& name : c.recording.names()) {
    const auto& x = again.column(name);
    const auto& y = c.recording.column(name);
    ASSERT_EQ(x.size(), y.size());
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - y[i]));
    EXPECT_LE(worst, 1e-12) << name << " (deg/s)";
  }
  fs::remove(file);
  // Same recording and request, same model and file, bit for bit (the summary's timings aside).
  EXPECT_EQ(a.model->to_json(), b.model->to_json());
  EXPECT_EQ(a.extra.at("training"), b.extra.at("training"));
}

INSTANTIATE_TEST_SUITE_P(EveryFitter, ModelFitterProperties, ::testing::ValuesIn(model_fitters().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace gyrosid
