// One property suite run over every model kind `calibrate` fits (solvers/calibrate.h's model_fitters()): its
// help names it, an unknown option is refused by name before any data is read, and a fit to a simulated dual
// scan is usable, removes most of the recorded error, loads back through the model kinds' registry to the
// same predictions, and repeats bit for bit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "error_of.h"
#include "model/calibration_model.h"
#include "model/dataset.h"
#include "model/model_kinds.h"
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
  const CalibrationResult a = calibrate(dual_scan(), request), b = calibrate(dual_scan(), request);
  ASSERT_TRUE(a.summary.usable()) << a.summary.message;
  EXPECT_GE(a.summary.iterations, 1);
  EXPECT_EQ(a.summary.iterations, static_cast<int>(a.summary.cost_history.size()));
  const Dataset d = make_dataset(dual_scan(), a.model->features(), a.model->target());
  const Eigen::VectorXd predicted = a.model->predict(d);
  const double left = rms(d.target - predicted) / rms(d.target);
  RecordProperty("residual_share_percent", std::to_string(100.0 * left));  // --gtest_output=xml shows it per fitter
  EXPECT_LT(left, 0.2) << "the fit leaves most of the recorded error";
  // Loadable by the model kinds' registry, to the same predictions.
  const fs::path file = fs::temp_directory_path() / ("gyrosid_fitter_" + GetParam() + ".json");
  save_model(file, *a.model, nlohmann::json::object());
  EXPECT_NE(model_kinds().find(load_model(file)->kind()), nullptr);
  EXPECT_EQ(load_model(file)->predict(d), predicted);
  fs::remove(file);
  // Same recording and request, same model, bit for bit.
  EXPECT_EQ(a.model->to_json(), b.model->to_json());
}

INSTANTIATE_TEST_SUITE_P(EveryFitter, ModelFitterProperties, ::testing::ValuesIn(model_fitters().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace gyrosid
