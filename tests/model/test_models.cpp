// Calibration models: planted coefficients recovered, JSON round trip, C export compiled and compared.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "model/averaging_bias.h"
#include "model/classical_model.h"
#include "model/fit_notes.h"
#include "model/greybox_fit.h"
#include "model/hybrid_model.h"
#include "model/model_kinds.h"
#include "model/physics_terms.h"
#include "model/terms/term_kinds.h"
#include "error_of.h"
#include "model_samples.h"
#include "model/rbf_network.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;
using namespace units;

// Inputs spanning the calibration domain: rate in [-100, 100] deg/s, temperature in [-20, 60] C.
Dataset random_dataset(std::size_t n, std::uint64_t seed) {
  RandomStream r(seed, "dataset");
  Dataset d;
  d.features = {"measured_rate", "temperature"};
  d.x.resize(static_cast<Eigen::Index>(n), 2);
  for (std::size_t i = 0; i < n; ++i) {
    d.x(static_cast<Eigen::Index>(i), 0) = dps_to_radps(-100 + 200 * r.uniform());
    d.x(static_cast<Eigen::Index>(i), 1) = -20 + 80 * r.uniform();
    d.t_s.push_back(static_cast<double>(i));
  }
  d.measured = d.x.col(0);
  d.reference = d.x.col(0);  // the error is planted in the target; the rates are the true ones
  d.target = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  return d;
}

TEST(ClassicalModel, RecoversPlantedPolynomialCoefficients) {
  ClassicalModel truth(default_features(), ModelTarget::error);
  truth.rate_scale = dps_to_radps(100);
  truth.temperature_reference = 20;
  truth.temperature_scale = 40;
  truth.bias = Eigen::Vector4d(dph_to_radps(-15), dph_to_radps(3), dph_to_radps(-1.5), dph_to_radps(0.7));
  truth.sf_temperature = Eigen::Vector3d(0, 120e-6, -40e-6);
  truth.sf_rate.resize(7);
  truth.sf_rate << 50e-6, 30e-6, -700e-6, 20e-6, 60e-6, 0, -10e-6;
  Dataset d = random_dataset(4000, 1);
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    const double x[2] = {d.x(i, 0), d.x(i, 1)};
    d.target(i) = truth.predict(x);
  }
  SolveSummary s;
  const auto fit = fit_classical(d, ClassicalOptions{}, &s);
  // The fit chooses its own scalings; compare the polynomials, not the raw coefficients.
  for (double t : {-20.0, 0.0, 33.3, 60.0}) {
    for (double w : {-100.0, -7.0, 0.5, 88.0}) {
      const double x[2] = {dps_to_radps(w), t};
      EXPECT_NEAR(fit->predict(x), truth.predict(x), 1e-12 * dps_to_radps(1)) << t << " C, " << w << " deg/s";
    }
  }
  EXPECT_EQ(s.termination, Termination::converged);
  EXPECT_LT(s.details["rms_residual_dph"].get<double>(), 1e-8);
  EXPECT_EQ(fit_notes_of(s.details).parameters, 4 + 2 + 7);
}

// sf_cross_order: the rate shape's coefficients polynomial in temperature (v^i u^k w). A planted surface whose
// rate^2 coefficient grows with temperature, like the reference FOG's, is reproduced exactly with the cross
// terms, and the thesis's separable form cannot hold it.
TEST(ClassicalModel, CrossTermsRecoverARateShapeThatMovesWithTemperature) {
  ClassicalModel truth(default_features(), ModelTarget::error);
  truth.rate_scale = dps_to_radps(100);
  truth.temperature_reference = 20;
  truth.temperature_scale = 40;
  truth.bias = Eigen::Vector2d(dph_to_radps(-15), dph_to_radps(3));
  truth.sf_temperature = Eigen::Vector2d(0, 120e-6);
  truth.sf_rate = Eigen::Vector4d(50e-6, 60e-6, -650e-6, 25e-6);
  truth.sf_cross = (Eigen::MatrixXd(2, 3) << 48e-6, -200e-6, 10e-6, 0.0, -64e-6, 0.0).finished();
  Dataset d = random_dataset(4000, 3);
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    const double x[2] = {d.x(i, 0), d.x(i, 1)};
    d.target(i) = truth.predict(x);
  }
  ClassicalOptions o;
  o.bias_order = 1, o.sf_temperature_order = 1, o.sf_rate_order = 3, o.sf_cross_order = 2;
  SolveSummary s;
  const auto fit = fit_classical(d, o, &s);
  for (double t : {-20.0, 0.0, 33.3, 60.0}) {
    for (double w : {-100.0, -7.0, 0.5, 88.0}) {
      const double x[2] = {dps_to_radps(w), t};
      EXPECT_NEAR(fit->predict(x), truth.predict(x), 1e-12 * dps_to_radps(1)) << t << " C, " << w << " deg/s";
    }
  }
  EXPECT_EQ(fit_notes_of(s.details).parameters, 2 + 1 + 4 + 2 * 3);
  EXPECT_LT(s.details["rms_residual_dph"].get<double>(), 1e-8);
  o.sf_cross_order = 0;  // separable: the temperature-dependent rate^2 term is out of reach (7.5 deg/h rms left)
  fit_classical(d, o, &s);
  EXPECT_GT(s.details["rms_residual_dph"].get<double>(), 3.0);
}

// A rate table at one temperature and a soak at rest: the columns in the held input are left out (coefficient 0,
// named in the summary) and the rest is recovered - at rest the rate columns would otherwise fit the noise in
// the measured rate. Three table rates cannot carry a sixth-order rate polynomial: that is still an error.
TEST(ClassicalModel, LeavesOutWhatAHeldInputCannotDetermine) {
  ClassicalModel truth(default_features(), ModelTarget::error);
  truth.rate_scale = dps_to_radps(100), truth.temperature_reference = 20, truth.temperature_scale = 40;
  truth.bias = Eigen::Vector4d(dph_to_radps(-15), dph_to_radps(3), dph_to_radps(-1.5), dph_to_radps(0.7));
  truth.sf_temperature = Eigen::Vector3d(0, 120e-6, -40e-6);
  truth.sf_rate.resize(7);
  truth.sf_rate << 50e-6, 30e-6, -700e-6, 20e-6, 60e-6, 0, -10e-6;
  auto plant = [&](Dataset& d) {
    for (Eigen::Index i = 0; i < d.size(); ++i) {
      const double x[2] = {d.x(i, 0), d.x(i, 1)};
      d.target(i) = truth.predict(x);
    }
  };
  Dataset one_temperature = random_dataset(2000, 2);
  one_temperature.x.col(1).setConstant(25.0);
  plant(one_temperature);
  SolveSummary s;
  auto fit = fit_classical(one_temperature, ClassicalOptions{}, &s);
  EXPECT_EQ(fit_notes_of(s.details).physics_left_out.value().columns,
            (std::vector<std::string>{"bias v^1", "bias v^2", "bias v^3", "sf_temperature v^1", "sf_temperature v^2"}));
  for (double w : {-100.0, -7.0, 0.5, 88.0}) {
    const double x[2] = {dps_to_radps(w), 25.0};
    EXPECT_NEAR(fit->predict(x), truth.predict(x), 1e-12 * dps_to_radps(1)) << w << " deg/s";
  }
  Dataset at_rest = random_dataset(2000, 4);
  RandomStream r(4, "at-rest");
  for (Eigen::Index i = 0; i < at_rest.size(); ++i) at_rest.x(i, 0) = at_rest.reference(i) = 0.0;
  plant(at_rest);
  for (Eigen::Index i = 0; i < at_rest.size(); ++i) {  // the gyro's noise is all its rate input holds at rest
    at_rest.x(i, 0) = at_rest.target(i) += dph_to_radps(5.0) * r.normal();
  }
  fit = fit_classical(at_rest, ClassicalOptions{}, &s);
  EXPECT_EQ(fit_notes_of(s.details).physics_left_out.value().columns.size(), 2u + 7u);
  EXPECT_TRUE(fit->sf_rate.isZero() && fit->sf_temperature.isZero());
  for (double t : {-20.0, 0.0, 33.3, 60.0}) {
    const double x[2] = {0.0, t};
    EXPECT_NEAR(radps_to_dph(fit->predict(x)), radps_to_dph(truth.predict(x)), 0.5) << t << " C";
  }
  Dataset three_rates = random_dataset(300, 5);
  for (Eigen::Index i = 0; i < three_rates.size(); ++i) three_rates.x(i, 0) = three_rates.reference(i) = dps_to_radps(100.0 * (i % 3 - 1));
  try {
    fit_classical(three_rates, ClassicalOptions{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("does not determine all"));
  }
}

// A noise-free recording of a sensor with a planted unified model, its probe lagging the chamber and its
// coil lagging the probe by 90 s.
Recording planted_greybox_recording(GyroSensor* truth_out) {
  SensorSpec spec = without_noise(load_sensor_file("builtin:sensors/open_loop_fog.yaml"));
  auto& g = std::get<GyroSensor>(spec);
  g.errors.shupe_rad_per_c = dph_to_radps(4.0) * 60.0;  // 4 deg/h per C/min
  g.errors.scale_factor_asymmetry = 300e-6;
  g.thermal.coil_tau_s = 90.0;
  *truth_out = g;
  TrajectorySpec t = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  t.sampling = Sampling{6000, 0.0};
  return simulate(spec, t, 1).recording;
}

TEST(GreyboxModel, RecoversAPlantedUnifiedModelWithShupeAsymmetryAndLag) {
  GyroSensor truth;
  const Recording rec = planted_greybox_recording(&truth);
  GreyboxOptions o;
  o.surface_temperatures_c = {-60, -20, 0, 20, 25, 40, 60, 80};  // the truth's grid
  o.shupe = o.asymmetry = o.thermal_lag = true;
  o.ridge = 1e-12;
  const Dataset d = make_dataset(rec, greybox_features(o), ModelTarget::error);
  SolveSummary s;
  const auto m = fit_greybox(d, o, &s);
  // The lag search (grid, then BOBYQA on log tau) reports its own termination, not a fixed "solved".
  EXPECT_TRUE(s.usable()) << s.message;
  EXPECT_EQ(s.details["lag_evaluations"].get<int>(), s.evaluations);
  EXPECT_EQ(s.iterations, s.evaluations);
  EXPECT_NEAR(m->lag_tau_s(), 90.0, 1.0);
  EXPECT_NEAR(m->errors().shupe_rad_per_c / truth.errors.shupe_rad_per_c, 1.0, 0.02);
  EXPECT_NEAR(m->errors().scale_factor_asymmetry, 300e-6, 5e-6);
  // Bias polynomial against the truth's constant + cubic, over the calibrated range.
  for (double t = -20; t <= 60; t += 10) {
    const double truth_bias = truth.errors.bias_radps + truth.errors.bias_temperature_radps(t);
    EXPECT_NEAR(radps_to_dph(m->errors().bias_temperature_radps(t) + m->errors().bias_radps), radps_to_dph(truth_bias), 0.05) << t;
  }
  EXPECT_LT(s.details["rms_residual_dph"].get<double>(), 0.05);
  // Compensation with the fitted model removes the errors along the recording.
  const Eigen::VectorXd comp = compensate(*m, d);
  EXPECT_LT(radps_to_dph(std::sqrt((comp - d.reference).squaredNorm() / d.size())), 0.05);
}

}  // namespace
}  // namespace gyrosid

namespace gyrosid {
namespace {

// A model's regressors reproduce its prediction with the posterior's weights: the hybrid's physics and RBF
// columns at the inverted true rate.
TEST(HybridModel, RegressorsTimesWeightsArePredictionsAndSigmaIsTheQuadraticForm) {
  const auto m = testing_support::model_samples().at("hybrid")();
  const auto& h = dynamic_cast<const HybridModel&>(*m);
  Eigen::VectorXd weights(h.rbf().nodes() + h.coefficients().size());
  weights << h.rbf().weights, h.coefficients();
  Eigen::MatrixXd x(5, 2);
  x << dps_to_radps(-90), -15, dps_to_radps(-3), 0, 0, 25, dps_to_radps(40), 44, dps_to_radps(100), 61;
  const Eigen::MatrixXd reg = m->regressors(x);
  const PredictionWithSigma p = m->predict_with_sigma(x);
  const Eigen::MatrixXd cov = m->posterior()->covariance();
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double xi[2] = {x(i, 0), x(i, 1)};
    EXPECT_NEAR(reg.row(i).dot(weights), m->predict(xi), 1e-15);
    EXPECT_NEAR(p.value(i), m->predict(xi), 0.0);
    EXPECT_NEAR(p.sigma(i), std::sqrt(reg.row(i) * cov * reg.row(i).transpose()), 1e-12 * p.sigma(i));
  }
  EXPECT_THAT(testing_support::error_of([] { testing_support::model_samples().at("classical")()->regressors(Eigen::MatrixXd(1, 2)); }),
              ::testing::HasSubstr("no posterior"));
}

// Found by fuzzing: polynomial orders in a model file were converted to int without a check (1.8e86 is
// undefined behaviour). Orders are whole numbers in [0, 12] or a named error; valid ones round-trip.
// A kind registered whole (solvers/calibrate.h): incomplete, or under a name already taken (the toy's, from
// toy_model_kind.cpp), it is refused, and the registries are left as they were.
TEST(ModelKindPlugin, IncompleteOrTakenIsRefused) {
  const std::size_t kinds = model_kinds().names().size();
  ModelKindPlugin half{"half", "no fitter", model_kinds().at("classical").make, [] { return std::string("half"); }, nullptr,
                       [] { return testing_support::model_samples().at("classical")(); }};
  EXPECT_THAT(testing_support::error_of([&] { register_model_kind(half); }), ::testing::HasSubstr("'half': a plugin needs its loader, help, fitter and sample"));
  half.fit = model_fitters().at("classical").make;
  half.name = "poly2d";
  EXPECT_THAT(testing_support::error_of([&] { register_model_kind(half); }), ::testing::HasSubstr("model kind 'poly2d' registered twice"));
  EXPECT_EQ(model_kinds().names().size(), kinds);
  // Every kind but explained (written by explain) is fitted by model_fitters().
  EXPECT_EQ(model_fitters().names().size(), model_kinds().names().size() - 1);
}

TEST(PhysicsTerms, PolynomialOrdersFromFilesAreChecked) {
  const auto load = [](const char* text) { return Term::from_json(nlohmann::json::parse(text)); };
  const Term ok = load(R"({"kind": "scale_factor", "sf_orders": [[0, 1], [2, 3]]})");
  EXPECT_EQ(ok.size(), 2);
  EXPECT_EQ(Term::from_json(ok.to_json()).to_json(), ok.to_json());
  EXPECT_EQ(load(R"({"kind": "bias_temperature", "orders": [1, 2, 3]})").size(), 3);
  for (const char* bad : {R"({"kind": "bias_temperature", "orders": [1, 1.77778e86]})", R"({"kind": "bias_temperature", "orders": [-1]})",
                          R"({"kind": "bias_temperature", "orders": [1.5]})", R"({"kind": "scale_factor", "sf_orders": [[1]]})",
                          R"({"kind": "scale_factor", "sf_orders": [[1, "2"]]})"}) {
    EXPECT_THAT(testing_support::error_of([&] { load(bad); }), ::testing::HasSubstr("orders")) << bad;
  }
}

// The bias spline in temperature: beside a cubic, its truncated cubics span the not-a-knot cubic splines on
// its knots - a not-a-knot spline through a bump's values at the knots (the surface's own 1-D
// construction, sensor/spline_surface.h, independent of this basis) is reproduced between them by least
// squares to round-off; T is held to the grid; bad grids refused.
TEST(PhysicsTerms, TemperatureSplineBesideACubicSpansTheCubicSplines) {
  const std::vector<double> knots{-30, -5, 10, 32, 45, 70};
  const Term spline = Term::from_json(nlohmann::json::parse(R"({"kind": "bias_temperature_spline", "knots_c": [-30, -5, 10, 32, 45, 70]})"));
  ASSERT_EQ(spline.size(), 2);
  Signals s;
  const int n = 401;
  for (int k = 0; k < n; ++k) s.t_s.push_back(10.0 * k);
  s.rate = Eigen::VectorXd::Zero(n);
  s.temp_c = Eigen::VectorXd::LinSpaced(n, -30.0, 70.0);
  const TermScaling scaling = TermScaling::of(s);
  const std::vector<Term> terms{bias_term(), temperature_polynomial({1, 2, 3}), spline};
  const Eigen::MatrixXd x = design_matrix(terms, s, coil_temperature(s, 0.0), scaling);
  Eigen::MatrixXd values(6, 2);
  for (int i = 0; i < 6; ++i) values(i, 0) = values(i, 1) = std::exp(-std::pow((knots[static_cast<std::size_t>(i)] - 20.0) / 15.0, 2));
  const SplineSurface reference(knots, {-1.0, 1.0}, values, OutsideGridPolicy::clamp);
  Eigen::VectorXd y(n);
  for (int k = 0; k < n; ++k) y(k) = reference(s.temp_c(k), 0.0).value;
  const Eigen::VectorXd beta = x.colPivHouseholderQr().solve(y);
  EXPECT_LT((x * beta - y).cwiseAbs().maxCoeff(), 1e-10);
  // Held at the grid's ends.
  Signals beyond = s;
  beyond.temp_c = Eigen::VectorXd::Constant(n, 95.0);
  const Eigen::MatrixXd held = term_columns(spline, beyond, coil_temperature(beyond, 0.0), scaling);
  EXPECT_NEAR(held(0, 0), std::pow((70.0 - 10.0) / 20.0, 3), 1e-12);
  EXPECT_EQ(Term::from_json(spline.to_json()).to_json(), spline.to_json());
  for (const char* bad : {R"({"kind": "bias_temperature_spline", "knots_c": [10]})", R"({"kind": "bias_temperature_spline", "knots_c": [10, 5, 20]})"}) {
    EXPECT_THAT(testing_support::error_of([&] { Term::from_json(nlohmann::json::parse(bad)); }), ::testing::HasSubstr("strictly increasing")) << bad;
  }
  EXPECT_THAT(testing_support::error_of([&] { Term::from_json(nlohmann::json::parse(R"({"kind": "bias_temperature_spline", "knots_c": [0, 10, 20, 30]})")); }),
              ::testing::HasSubstr("at least five knots"));
}

}  // namespace
}  // namespace gyrosid

namespace gyrosid {
namespace {

// The probe's rate is the least-squares slope over +-30 s (at least one neighbour each side): the sliding sums
// agree with the regression written out sample by sample, across a gap and with jittered times.
TEST(PhysicsTerms, ProbeRateIsTheWindowedRegressionSlope) {
  RandomStream r(11, "probe");
  Signals s;
  double t = 0.0;
  for (int i = 0; i < 3000; ++i) {
    t += i == 1500 ? 200.0 : 0.1 * (0.8 + 0.4 * r.uniform());
    s.t_s.push_back(1e5 + t);  // far from zero: the sums are taken about an anchor
  }
  const auto n = static_cast<Eigen::Index>(s.t_s.size());
  s.temp_c.resize(n), s.rate = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) s.temp_c(i) = 25.0 + 5.0 * std::sin(0.01 * (s.t_s[static_cast<std::size_t>(i)] - 1e5)) + 0.01 * std::round(r.normal());
  const Eigen::VectorXd rate = coil_temperature(s, 0.0).rate_c_per_s;
  for (Eigen::Index i = 0; i < n; i += 37) {
    const double ti = s.t_s[static_cast<std::size_t>(i)];
    std::vector<double> tw, vw;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double tk = s.t_s[static_cast<std::size_t>(k)];
      if (std::abs(tk - ti) <= 30.0 || k == i - 1 || k == i + 1) tw.push_back(tk - ti), vw.push_back(s.temp_c(k));
    }
    double tm = 0, vm = 0;
    for (std::size_t k = 0; k < tw.size(); ++k) tm += tw[k] / tw.size(), vm += vw[k] / vw.size();
    double stt = 0, stv = 0;
    for (std::size_t k = 0; k < tw.size(); ++k) stt += (tw[k] - tm) * (tw[k] - tm), stv += (tw[k] - tm) * (vw[k] - vm);
    EXPECT_NEAR(rate(i), stv / stt, 1e-9 * (1.0 + std::abs(stv / stt))) << i;
  }
}

// f(w, T) = a w^2 + c (T - 20)^2: the block mean of f exceeds f at the block's mean inputs by a s_w^2 + c s_T^2,
// which the two-point rule gets exactly.
class Quadratic : public CalibrationModel {
 public:
  Quadratic() : CalibrationModel(default_features(), ModelTarget::error) {}
  static constexpr double a = 2.0, c = 3e-6;
  std::string_view kind() const override { return "quadratic"; }
  double predict(const double* x) const override { return a * x[0] * x[0] + c * (x[1] - 20.0) * (x[1] - 20.0); }
  nlohmann::json parameters_json() const override { return {}; }
  void export_c_body(CExport&) const override {}
};

TEST(AveragingBias, TheTwoPointRuleIsExactForAQuadratic) {
  Decimation d;
  d.factor = 10;
  d.inputs = {{"ref_rate_dps", 4.0, 8.0, {1.0, 4.0, 0.0}}, {"temp_c", 0.5, 1.0, {0.5, 0.1, 0.2}}};
  Dataset data;
  data.features = default_features();
  data.x = (Eigen::MatrixXd(3, 2) << 0.1, 25.0, -0.5, 10.0, 0.0, 20.0).finished();
  data.measured = data.x.col(0), data.reference = data.target = Eigen::VectorXd::Zero(3);
  data.t_s = {0.0, 1.0, 2.0};
  const AveragingBias b = averaging_bias(Quadratic(), data, d, 1.0);
  double largest = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double s_w = dps_to_radps(d.inputs[0].sd[static_cast<std::size_t>(i)]), s_t = d.inputs[1].sd[static_cast<std::size_t>(i)];
    largest = std::max(largest, radps_to_dph(Quadratic::a * s_w * s_w + Quadratic::c * s_t * s_t));
  }
  EXPECT_NEAR(b.largest_dph, largest, 1e-9 * largest);
  EXPECT_EQ(b.blocks, 3u);
  EXPECT_DOUBLE_EQ(b.threshold_dph, 0.1);
  EXPECT_EQ(b.blocks_over, 2u);  // the third block's rate does not move: its bias is c 0.2^2, far below 0.1 deg/h
  EXPECT_THAT(b.statement(), ::testing::HasSubstr("in 2 of 3 blocks"));
}

}  // namespace
}  // namespace gyrosid
