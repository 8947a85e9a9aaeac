// Property suites run over every registered model kind (model/model_kinds.h), as Sophus runs one suite
// over every group. Every kind, the triad included (AnyModelKind): its file loads back to the same file, a
// malformed one is an error naming it, a recording compensated through the SensorModel interface holds the
// columns and the rms it reports, and only a single gyro's kind loads where one is needed. Every single-gyro
// kind (ModelKind): JSON round trip to the bit, C export compiled and compared, compensation consistent
// with the prediction, a recording's prediction equal to the per-sample one at steady temperature,
// malformed parameters refused naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "core/units.h"
#include "model/compensate_recording.h"
#include "model/model_kinds.h"
#include "error_of.h"
#include "model_samples.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;
using testing_support::model_samples;

std::vector<std::array<double, 2>> probe_points() {
  std::vector<std::array<double, 2>> pts;
  for (double t : {-70.0, -20.0, 0.0, 24.9, 60.0, 85.0})
    for (double w : {-110.0, -100.0, -33.3, -1e-6, 0.0, 1e-6, 0.25, 47.0, 100.0}) pts.push_back({units::dps_to_radps(w), t});
  return pts;
}

class ModelKind : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<CalibrationModel> sample() const { return model_samples().at(GetParam())(); }
  // One directory per test and kind: ctest runs the tests of a kind in parallel processes.
  fs::path dir() const {
    std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();  // "Name/kind"
    std::replace(test.begin(), test.end(), '/', '_');
    return fs::temp_directory_path() / ("gyrosid_model_kind_" + test);
  }
  void TearDown() override { fs::remove_all(dir()); }
};

TEST(ModelKinds, EveryRegisteredKindHasASample) {
  for (const auto& name : model_kinds().names()) {
    EXPECT_TRUE(testing_support::sensor_model_samples().count(name)) << "no sample for model kind '" << name << "'";
  }
}

class AnyModelKind : public ModelKind {
 protected:
  std::unique_ptr<SensorModel> sensor_sample() const { return testing_support::sensor_model_samples().at(GetParam())(); }
};

TEST_P(AnyModelKind, ItsFileLoadsBackToTheSameFile) {
  const auto m = sensor_sample();
  EXPECT_EQ(m->kind(), GetParam());
  const nlohmann::json j = m->to_json();
  EXPECT_EQ(j.at("format"), kModelFormat);
  EXPECT_EQ(j.at("kind"), GetParam());
  const auto back = sensor_model_from_json(nlohmann::json::parse(j.dump()), "round trip");
  EXPECT_EQ(back->kind(), m->kind());
  EXPECT_EQ(back->gyros(), m->gyros());
  EXPECT_EQ(back->to_json().dump(), j.dump());
}

TEST_P(AnyModelKind, AMalformedFileIsAnErrorNamingIt) {
  nlohmann::json j = sensor_sample()->to_json();
  for (auto it = j.begin(); it != j.end();) it = (it.key() == "format" || it.key() == "kind") ? std::next(it) : j.erase(it);
  fs::create_directories(dir());
  const auto path = dir() / "broken.json";
  std::ofstream(path) << j.dump();
  EXPECT_THAT(testing_support::error_of([&] { load_sensor_model(path); }), ::testing::HasSubstr(path.string()));
}

// Where one gyro's model is needed (load_model: surface, explain, a triad's surfaces) a kind of three gyros
// is refused by name; a single gyro's loads.
TEST_P(AnyModelKind, OnlyASingleGyrosKindLoadsAsOne) {
  const auto m = sensor_sample();
  fs::create_directories(dir());
  const auto path = dir() / "model.json";
  std::ofstream(path) << m->to_json().dump();
  if (m->gyros() == 1) {
    EXPECT_EQ(load_model(path)->kind(), m->kind());
  } else {
    EXPECT_THAT(testing_support::error_of([&] { load_model(path); }),
                ::testing::AllOf(::testing::HasSubstr(path.string()), ::testing::HasSubstr(str_cat("of ", m->gyros(), " gyros"))));
  }
}

// A recording of the kind's gyros (one, or a triad's three) compensated through the interface: the file
// written holds the columns the result names, and the rms it reports is the written columns' against the
// reference (to the precision of the written digits).
TEST_P(AnyModelKind, ACompensatedFileHoldsWhatItsResultReports) {
  const auto m = sensor_sample();
  const std::vector<std::string> axes = m->gyros() == 1 ? std::vector<std::string>{""} : std::vector<std::string>{"_x", "_y", "_z"};
  Recording r("rec.csv");
  std::vector<double> t;
  for (int i = 0; i < 120; ++i) t.push_back(5.0 * i);
  r.set_column("t_s", t);
  for (std::size_t a = 0; a < axes.size(); ++a) {
    std::vector<double> ref, gyro;
    for (int i = 0; i < 120; ++i) {
      ref.push_back((i % 40 < 20 ? 60.0 : -25.0) * (1.0 + 0.3 * static_cast<double>(a)));
      gyro.push_back(ref.back() * (1 + 2e-4) + 0.004 * std::cos(0.3 * i + static_cast<double>(a)) + 1e-3);
    }
    r.set_column("ref_rate" + axes[a] + "_dps", ref), r.set_column("gyro" + axes[a] + "_dps", gyro);
    if (axes.size() == 3) r.set_column("accel" + axes[a] + "_mps2", std::vector<double>(t.size(), a == 2 ? -9.81 : 0.1));  // its g-sensitivity's input
  }
  std::vector<double> temp;
  for (int i = 0; i < 120; ++i) temp.push_back(20.0 + 25.0 * std::sin(0.03 * i));
  r.set_column("temp_c", temp);
  fs::create_directories(dir());
  write_recording(r, dir() / "in.csv");
  const CompensatedRecording result = m->compensate_file(dir() / "in.csv", dir() / "out.csv", "");
  const Recording out = read_recording(dir() / "out.csv");
  EXPECT_EQ(result.samples, 120u);
  double before = 0, after = 0;
  for (const auto& a : axes) {
    EXPECT_NE(result.added.find(a.empty() ? "compensated_dps" : "{x,y,z}"), std::string::npos) << result.added;
    for (std::size_t i = 0; i < out.rows(); ++i) {
      const double ref = out.column("ref_rate" + a + "_dps")[i];
      before += std::pow(out.column("gyro" + a + "_dps")[i] - ref, 2);
      after += std::pow(out.column("compensated" + a + "_dps")[i] - ref, 2);
    }
  }
  const double n = static_cast<double>(axes.size() * out.rows());
  ASSERT_TRUE(result.rms_before_dph && result.rms_after_dph);
  EXPECT_NEAR(*result.rms_before_dph, 3600.0 * std::sqrt(before / n), 1e-9 * *result.rms_before_dph);
  EXPECT_NEAR(*result.rms_after_dph, 3600.0 * std::sqrt(after / n), 1e-6 * *result.rms_after_dph);
  if (m->gyros() == 3) {
    EXPECT_THAT(testing_support::error_of([&] { m->compensate_file(dir() / "in.csv", dir() / "y.csv", "y"); }), ::testing::HasSubstr("--axis"));
  }
}

TEST_P(ModelKind, JsonRoundTripReproducesEveryPrediction) {
  const auto m = sample();
  const auto variant = testing_support::sample_variants().find(GetParam());
  EXPECT_EQ(m->kind(), variant == testing_support::sample_variants().end() ? GetParam() : variant->second);
  const auto path = dir() / "model.json";
  save_model(path, *m, {{"note", "test"}});
  const auto back = load_model(path);
  EXPECT_EQ(back->kind(), m->kind());
  EXPECT_EQ(back->features(), m->features());
  for (const auto& x : probe_points()) EXPECT_EQ(back->predict(x.data()), m->predict(x.data())) << x[0] << ", " << x[1];
}

TEST_P(ModelKind, CExportCompilesAndReproducesTheCppCompensation) {
  const auto m = sample();
  const std::string prefix = "gyro_" + GetParam();
  m->export_c(dir(), prefix);
  std::ofstream driver(dir() / (prefix + "_main.c"));
  driver << "#include <stdio.h>\n#include \"" << prefix << ".h\"\nint main(void) {\n  double x[2];\n"
         << "  while (scanf(\"%lf %lf\", &x[0], &x[1]) == 2) printf(\"%.17g\\n\", " << prefix << "_compensate(x, x[0]));\n"
         << "  return 0;\n}\n";
  driver.close();
  const std::string exe = (dir() / prefix).string();
  const std::string compile = "cc -std=c99 -pedantic -Wall -Werror -O2 -o " + exe + " " + (dir() / (prefix + ".c")).string() + " " +
                              (dir() / (prefix + "_main.c")).string() + " -lm 2>&1";
  ASSERT_EQ(std::system(compile.c_str()), 0) << compile;
  const auto points = probe_points();
  std::ofstream in(dir() / "in.txt");
  in.precision(17);
  for (const auto& x : points) in << x[0] << " " << x[1] << "\n";
  in.close();
  FILE* pipe = popen((exe + " < " + (dir() / "in.txt").string()).c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  for (const auto& x : points) {
    double c = 0;
    ASSERT_EQ(std::fscanf(pipe, "%lf", &c), 1);
    const double cpp = x[0] - m->predict(x.data());
    EXPECT_NEAR(c, cpp, 1e-12 * std::max(1.0, std::abs(cpp))) << "at " << x[0] << ", " << x[1];
  }
  pclose(pipe);
}

// At a constant temperature (no rate of change, no history) a recording's prediction is the per-sample
// one, and compensation subtracts it from the measured rate.
TEST_P(ModelKind, RecordingPredictionAtSteadyTemperatureIsPerSample) {
  const auto m = sample();
  Dataset d;
  d.features = m->features();
  const auto points = probe_points();
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  d.x.resize(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    d.x(i, 0) = points[static_cast<std::size_t>(i)][0];
    d.x(i, 1) = 24.9;
    d.t_s.push_back(static_cast<double>(i));
  }
  d.measured = d.x.col(0);
  d.reference = d.target = Eigen::VectorXd::Constant(n, NAN);
  const Eigen::VectorXd along = m->predict(d), comp = compensate(*m, d);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double single = m->predict(d.x.row(i).eval().data());
    EXPECT_NEAR(along(i), single, 1e-15 + 1e-12 * std::abs(single)) << i;
    EXPECT_DOUBLE_EQ(comp(i), d.measured(i) - along(i));
  }
}

// A recording with temperature ramps and rate steps, its rows compensated a chunk of 7 at a time from file to
// file (compensate_file), is byte for byte what compensating it whole writes - for a model with dynamics
// (pointwise() false: run over the whole recording first) as for one without; and --axis on a triad adds
// the same numbers under compensated_<axis>_dps.
TEST_P(ModelKind, CompensatingAFileAChunkAtATimeWritesWhatTheWholeRecordingGives) {
  const auto m = sample();
  Recording r("rec.csv");
  std::vector<double> t, ref, temp, gyro;
  for (int i = 0; i < 200; ++i) {
    t.push_back(10.0 * i), ref.push_back(i % 50 < 25 ? 80.0 : -30.0 + 0.3 * i), temp.push_back(20.0 + 30.0 * std::sin(0.02 * i));
    gyro.push_back(ref.back() * (1 + 1e-4) + 0.01 * std::cos(0.3 * i));
  }
  r.set_meta("sensor", "test");
  r.set_column("t_s", t), r.set_column("ref_rate_dps", ref), r.set_column("temp_c", temp), r.set_column("gyro_dps", gyro);
  fs::create_directories(dir());
  write_recording(r, dir() / "in.csv");
  write_recording(compensate_recording(*m, r).recording, dir() / "whole.csv");
  const CompensatedRecording streamed = compensate_file(*m, dir() / "in.csv", dir() / "chunks.csv", "", 7);
  const auto text = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  // Every column to the bit, but a posterior's sigma sqrt(h' P h), whose matrix products round by the number of
  // rows they see: to 1e-12 of itself.
  const Recording chunks = read_recording(dir() / "chunks.csv"), all = read_recording(dir() / "whole.csv");
  ASSERT_EQ(chunks.names(), all.names());
  EXPECT_EQ(chunks.metadata(), all.metadata());
  for (const auto& name : all.names()) {
    for (std::size_t i = 0; i < all.rows(); ++i) {
      if (name == "compensated_sigma_dps") EXPECT_NEAR(chunks.column(name)[i], all.column(name)[i], 1e-12 * all.column(name)[i]) << i;
      else EXPECT_EQ(chunks.column(name)[i], all.column(name)[i]) << name << "[" << i << "]";
    }
  }
  if (!all.has("compensated_sigma_dps")) {
    EXPECT_EQ(text(dir() / "chunks.csv"), text(dir() / "whole.csv"));
  }
  const CompensatedRecording whole = compensate_recording(*m, r);
  EXPECT_EQ(streamed.samples, 200u);
  EXPECT_NEAR(*streamed.rms_after_dph, *whole.rms_after_dph, 1e-9 * *whole.rms_after_dph);
  EXPECT_EQ(streamed.coverage_95.has_value(), whole.coverage_95.has_value());
  Recording triad("triad.csv");
  triad.set_column("t_s", t);
  for (const char* a : {"x", "y", "z"}) {
    triad.set_column(std::string("ref_rate_") + a + "_dps", a == std::string("y") ? ref : std::vector<double>(t.size(), 1.0));
    triad.set_column(std::string("gyro_") + a + "_dps", a == std::string("y") ? gyro : std::vector<double>(t.size(), 1.0));
  }
  triad.set_column("temp_c", temp);
  write_recording(triad, dir() / "triad.csv");
  compensate_file(*m, dir() / "triad.csv", dir() / "triad_y.csv", "y", 7);
  const Recording back = read_recording(dir() / "triad_y.csv");
  EXPECT_EQ(back.column("compensated_y_dps"), read_recording(dir() / "whole.csv").column("compensated_dps"));
}

TEST_P(ModelKind, MalformedParametersAreErrorsNamingTheFile) {
  const auto m = sample();
  nlohmann::json j = m->to_json();
  j["parameters"] = nlohmann::json::object();
  fs::create_directories(dir());
  const auto path = dir() / "broken.json";
  std::ofstream(path) << j.dump();
  EXPECT_THAT(testing_support::error_of([&] { load_model(path); }), ::testing::HasSubstr(path.string()));
}

TEST(ModelFiles, MalformedFilesAreClearErrors) {
  const auto dir = fs::temp_directory_path() / "gyrosid_bad_model";
  fs::create_directories(dir);
  std::ofstream(dir / "a.json") << "{\"format\": \"something\"}";
  std::ofstream(dir / "b.json") << "not json";
  std::ofstream(dir / "c.json") << "{\"format\": \"gyrosid-model/1\", \"kind\": \"spline\", \"features\": [\"measured_rate\"], "
                                   "\"target\": \"error\", \"parameters\": {}}";
  for (const char* f : {"a.json", "b.json", "c.json"}) {
    EXPECT_THAT(testing_support::error_of([&] { load_model(dir / f); }), ::testing::HasSubstr(f));
  }
  EXPECT_THAT(testing_support::error_of([&] { load_model(dir / "c.json"); }),
              ::testing::HasSubstr("unknown model kind 'spline'; known: " + model_kinds().known()));
  fs::remove_all(dir);
}

// The kinds of one gyro: every registered kind whose sample is a CalibrationModel.
std::vector<std::string> single_gyro_kinds() {
  std::vector<std::string> out;
  for (const auto& name : model_kinds().names()) {
    if (model_samples().count(name)) out.push_back(name);
  }
  return out;
}
INSTANTIATE_TEST_SUITE_P(EveryKind, AnyModelKind, ::testing::ValuesIn(model_kinds().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });
INSTANTIATE_TEST_SUITE_P(EveryKind, ModelKind, ::testing::ValuesIn(single_gyro_kinds()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });
std::vector<std::string> variant_names() {
  std::vector<std::string> out;
  for (const auto& [name, kind] : testing_support::sample_variants()) out.push_back(name);
  return out;
}
INSTANTIATE_TEST_SUITE_P(Variants, ModelKind, ::testing::ValuesIn(variant_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// The relative rbf is the plain one times the measured rate, at every probe point and in its regressors.
TEST(RbfNetwork, AnOutputFactorMultipliesTheNetworkByThatInput) {
  const auto relative = testing_support::sample_relative_rbf();
  auto plain = std::make_unique<RbfNetwork>(dynamic_cast<const RbfNetwork&>(*relative));
  plain->output_factor = -1;
  for (const auto& x : probe_points()) EXPECT_DOUBLE_EQ(relative->predict(x.data()), x[0] * plain->predict(x.data())) << x[0] << ", " << x[1];
  plain->weight_posterior = WeightPosterior::of_covariance(1e-6 * Eigen::MatrixXd::Identity(plain->nodes() + 1, plain->nodes() + 1), 0.0);
  auto scaled = std::make_unique<RbfNetwork>(*plain);
  scaled->output_factor = 0;
  const Eigen::MatrixXd x = (Eigen::MatrixXd(3, 2) << 0.5, 10.0, -1.2, 30.0, 0.0, 20.0).finished();
  const Eigen::MatrixXd h = plain->regressors(x), hs = scaled->regressors(x);
  for (Eigen::Index i = 0; i < x.rows(); ++i) EXPECT_EQ(hs.row(i), (x(i, 0) * h.row(i)).eval()) << i;
}

}  // namespace
}  // namespace gyrosid
