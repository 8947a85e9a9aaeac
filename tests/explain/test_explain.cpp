// Missing-physics discovery: its numerical parts against analytic truths (Burg's AR estimate, projections,
// the spline basis, the model's inversion) and the whole on recordings with planted effects - each found
// by name with its parameter inside its interval, nothing found where nothing is missing, and a structure
// outside the library reported as unexplained with the channel it follows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

#include "core/config.h"
#include "core/random.h"
#include "core/thermal_lag.h"
#include "core/units.h"
#include "explain/explain.h"
#include "explain/linear_fit.h"
#include "explain/simulation.h"
#include "noise/state_space.h"
#include "read_file.h"
#include "model/dataset.h"
#include "model/explained_model.h"
#include "model/terms/term_kinds.h"
#include "report/explain_json.h"
#include "report/explain_report.h"
#include "sensor/sensor_config.h"
#include "model/calibration_model.h"
#include "solvers/calibrate.h"
#include "sensor/spline_surface.h"
#include "sim/simulate.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid::explain {
namespace {

// A polynomial FOG: bias cubic in T, scale factor quadratic in rate and linear in T, white noise 10 deg/h.
constexpr const char* kSensor = R"(
kind: gyro
name: polynomial FOG
bias:
  constant_dph: -15
  temperature: {reference_c: 25, coefficients_dph: [0, 0.12, -0.0025, 0.00004]}
scale_factor:
  temperature: {reference_c: 25, coefficients_ppm: [0, 2.0]}
  rate: {coefficients_ppm: [40, 0.6, -0.065]}
noise: {white_dph_at_1hz: 10}
thermal: {tau_s: 300}
)";

// Four thermal cycles -40..40 C at 5 C/min with rate cycles, 1 Hz: 128 min, 7680 samples.
constexpr const char* kTrajectory = R"(
kind: test_cycles
name: explain test
temperature_c: [-40, 40]
scan_rate_c_per_min: 5
rate_dps: [-100, 100]
temperature_cycles: 4
rate_cycles_per_temperature_cycle: 8
boundary_scan_min: 0
chamber: {rate_limit_c_per_min: 5}
sampling: {rate_hz: 1}
)";

Recording simulate_sensor(const SensorSpec& sensor, std::uint64_t seed) {
  return simulate(sensor, load_trajectory(ConfigNode::parse(kTrajectory, "test trajectory")), seed).recording;
}

Recording simulate_with(const std::string& extra_sensor_yaml, std::uint64_t seed) {
  return simulate_sensor(load_sensor(ConfigNode::parse(std::string(kSensor) + extra_sensor_yaml, "test sensor")), seed);
}

ExplainOptions fast() {
  ExplainOptions o;
  o.selection.bootstrap = 199;
  o.baseline_form = BaselineForm::polynomial;
  return o;
}

const FoundEffect* effect(const ExplainSummary& summary, const std::string& id) {
  for (const auto& e : summary.effects) {
    if (e.id == id) return &e;
  }
  return nullptr;
}

const PhysicalParameter& parameter(const FoundEffect& e, const std::string& name) {
  for (const auto& p : e.parameters) {
    if (p.name == name) return p;
  }
  throw std::runtime_error("no parameter " + name + " in " + e.id);
}

std::string ids(const ExplainSummary& s) {
  std::string out;
  for (const auto& e : s.effects) out += e.id + " ";
  return out;
}

std::string unexplained(const ExplainSummary& s) {
  std::string out;
  for (const auto& u : s.unexplained) out += std::string(to_string(u.kind)) + (u.channel ? ":" + *u.channel : "") + " ";
  return out;
}

// White noise plus a rate random walk: the Allan fit recovers its curve, and the Kalman whitener turns the
// sum into white noise of unit variance (no lag-1 correlation, no slow wander left).
TEST(NoiseModel, FitsWhiteNoisePlusRandomWalkAndWhitensIt) {
  RandomStream rng(7, "noise");
  const Eigen::Index n = 40000;
  const double sigma = 10.0, q = 0.02;  // per-sample white sd; random-walk increment variance
  Eigen::VectorXd x(n);
  double walk = 0.0;
  for (Eigen::Index t = 0; t < n; ++t) {
    walk += std::sqrt(q) * rng.normal();
    x(t) = walk + sigma * rng.normal();
  }
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = i;
  const auto runs = contiguous_runs(rows, std::vector<int>(static_cast<std::size_t>(n), 0));
  const NoiseModel m = fit_noise_model(x, runs, 1.0);
  // The slow part may come out as the random walk or as a Gauss-Markov process with a correlation time beyond
  // the record - the same Allan curve; what must match is that curve.
  EXPECT_NEAR(std::sqrt(m.white_var), sigma, 0.05 * sigma);
  for (double tau : {100.0, 1000.0}) {  // longer averaging times have too few independent averages
    const double truth = sigma * sigma / tau + q * tau / 3.0;
    EXPECT_NEAR(m.allan_variance(tau) / truth, 1.0, 0.3) << tau;
  }
  std::vector<double> t(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i);
  const Eigen::VectorXd whitened = Whitener(m, rows, t).apply(x);
  const Eigen::VectorXd w = whitened.tail(n - 10);
  EXPECT_NEAR(w.squaredNorm() / static_cast<double>(w.size()), 1.0, 0.03);
  const double r1 = w.head(w.size() - 1).dot(w.tail(w.size() - 1)) / w.squaredNorm();
  EXPECT_LT(std::abs(r1), 0.02);
  // The variance of 1000-sample means of the whitened series is that of white noise (1/1000), not the walk's.
  double ss = 0.0;
  const Eigen::Index blocks = w.size() / 1000;
  for (Eigen::Index b = 0; b < blocks; ++b) ss += std::pow(w.segment(b * 1000, 1000).mean(), 2);
  EXPECT_LT(ss / static_cast<double>(blocks), 3.0 / 1000.0);
  // Pure white noise is fitted as white: nothing slow.
  Eigen::VectorXd white(n);
  for (Eigen::Index t = 0; t < n; ++t) white(t) = sigma * rng.normal();
  const NoiseModel mw = fit_noise_model(white, runs, 1.0);
  EXPECT_NEAR(std::sqrt(mw.white_var), sigma, 0.03 * sigma);
  EXPECT_LT(mw.allan_variance(5000.0), 1.5 * sigma * sigma / 5000.0);
}

TEST(LinearFit, NewDirectionsAreOrthonormalAndEmptyInsideTheSpan) {
  RandomStream rng(3, "fit");
  Eigen::MatrixXd a(500, 3), b(500, 2);
  for (Eigen::Index i = 0; i < 500; ++i) {
    for (Eigen::Index j = 0; j < 3; ++j) a(i, j) = rng.normal();
    for (Eigen::Index j = 0; j < 2; ++j) b(i, j) = rng.normal();
  }
  const WhitenedFit f = fit_whitened(a, a.col(0) * 2.0 - a.col(2));
  EXPECT_EQ(f.rank, 3);
  EXPECT_NEAR(f.beta(0), 2.0, 1e-12);
  EXPECT_NEAR(f.beta(2), -1.0, 1e-12);
  EXPECT_LT(f.rss, 1e-20);
  EXPECT_EQ(new_directions(a * Eigen::Vector3d(1, 2, 3), f.basis).cols(), 0);  // inside the span
  const Eigen::MatrixXd z = new_directions(b, f.basis);
  ASSERT_EQ(z.cols(), 2);
  EXPECT_LT((z.transpose() * z - Eigen::Matrix2d::Identity()).norm(), 1e-12);
  EXPECT_LT((f.basis.transpose() * z).norm(), 1e-12);
  // A dependent pair of columns is dropped to rank 1.
  Eigen::MatrixXd dep(500, 2);
  dep << a.col(0), 3.0 * a.col(0);
  EXPECT_EQ(fit_whitened(dep, a.col(1)).rank, 1);
}

// The likelihood's residual sum of squares (a chunked QR of [X y], whitened_rss) agrees with the full QR
// fit's (fit_whitened, which forms Q) - on a matrix taller than several chunks, with a dependent column
// (rank 5 of 6) and columns of very different scale.
TEST(LinearFit, ChunkedResidualSumOfSquaresAgreesWithTheFullQr) {
  RandomStream rng(4, "rss");
  const Eigen::Index n = 2345;
  Eigen::MatrixXd x(n, 6);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < 5; ++j) x(i, j) = rng.normal() * std::pow(10.0, j - 2);
    x(i, 5) = x(i, 1) - 3.0 * x(i, 3);
    y(i) = x(i, 0) + 0.5 * x(i, 4) + rng.normal();
  }
  const WhitenedFit full = fit_whitened(x, y);
  ASSERT_EQ(full.rank, 5);
  EXPECT_NEAR(whitened_rss(x, y), full.rss, 1e-10 * full.rss);
  EXPECT_NEAR(full.rss / (n - 5), 1.0, 0.1);  // unit-variance noise: the sanity of the reference itself
  // y inside the span: nothing left.
  EXPECT_LT(whitened_rss(x, x.col(2) - x.col(5)), 1e-18 * x.col(2).squaredNorm());
}

// Terms' columns along a record at rest (rate 0): times t_s (s), probe temperatures temp_c (C), no coil lag.
struct TermsAtRest {
  Signals s;
  CoilTemperature coil;
  TermScaling sc;
  TermsAtRest(std::vector<double> t_s, const Eigen::VectorXd& temp_c) {
    s.t_s = std::move(t_s);
    s.rate = Eigen::VectorXd::Zero(temp_c.size());
    s.temp_c = temp_c;
    coil = coil_temperature(s, 0.0);
    sc = TermScaling::of(s);
  }
  // Probe temperatures every 600 s.
  static TermsAtRest every_ten_minutes(const std::vector<double>& temp_c) {
    std::vector<double> t(temp_c.size());
    for (std::size_t k = 0; k < t.size(); ++k) t[k] = 600.0 * static_cast<double>(k);
    return {t, Eigen::Map<const Eigen::VectorXd>(temp_c.data(), static_cast<Eigen::Index>(temp_c.size()))};
  }
  Eigen::MatrixXd columns(const Term& t) const { return design_matrix({t}, s, coil, sc); }
};

// The hysteresis term is the play operator of half-width width/2 from its neutral state, scaled to +-1/2:
// along 0 -> 10 -> 0 C with width 2 C it is x/2 for the first degree, +1/2 while heating, 0 one degree
// after the turn, -1/2 from two degrees after it.
TEST(PhysicsTerms, HysteresisIsThePlayOperatorFromItsNeutralState) {
  const std::vector<double> temp{0.0, 0.5, 1.0, 4.0, 10.0, 9.0, 8.0, 5.0, 0.0};
  const auto n = static_cast<Eigen::Index>(temp.size());
  const Eigen::MatrixXd x = TermsAtRest::every_ten_minutes(temp).columns(hysteresis_term(2.0));
  const std::vector<double> expected{0.0, 0.25, 0.5, 0.5, 0.5, 0.0, -0.5, -0.5, -0.5};
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_NEAR(x(k, 0), expected[static_cast<std::size_t>(k)], 1e-12) << k;
}

// A loop of two widths is the two plays side by side; the model file keeps both widths, and a new width_c
// (the refit's parameter) leaves the second where it is.
TEST(PhysicsTerms, ATwoWidthHysteresisIsTwoPlaysAndSurvivesItsJson) {
  const std::vector<double> temp{0.0, 0.5, 1.0, 4.0, 10.0, 9.0, 8.0, 5.0, 0.0, 3.0};
  const auto n = static_cast<Eigen::Index>(temp.size());
  const TermsAtRest at = TermsAtRest::every_ten_minutes(temp);
  const Term two = hysteresis_term(2.0, 6.0);
  const Eigen::MatrixXd x = at.columns(two);
  ASSERT_EQ(x.cols(), 2);
  EXPECT_EQ(two->column_names(), (std::vector<std::string>{"hysteresis", "hysteresis_2"}));
  EXPECT_LT((x.col(0) - at.columns(hysteresis_term(2.0)).col(0)).cwiseAbs().maxCoeff(), 1e-15);
  // Width 6 C (half-width 3): (T - 0)/6 until T passes 3 C, then +1/2; after the turn at 10 C the play holds
  // at 7 C, so (T - 7)/6, until T falls below 4 C; back up from 0 C it holds at 3 C.
  const std::vector<double> wide{0.0, 0.5 / 6, 1.0 / 6, 0.5, 0.5, 2.0 / 6, 1.0 / 6, -2.0 / 6, -0.5, 0.0};
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_NEAR(x(k, 1), wide[static_cast<std::size_t>(k)], 1e-12) << k;
  EXPECT_LT((at.columns(Term::from_json(two.to_json())) - x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(two.with_parameter(3.0).to_json().at("second_width_c").get<double>(), 6.0);
}

// A step that recovers is the step and exp(-(t - t_s) / tau) from t_s on; the model file keeps its recovery,
// a new t_s (the refit's parameter) keeps the recovery's time constant, and a trend cannot have one; a curved
// trend is the trend and its square.
TEST(PhysicsTerms, ARecoveringStepAndACurvedTrendAreTheirColumnsAndSurviveTheirJson) {
  const Eigen::Index n = 6;
  const TermsAtRest at({0.0, 100.0, 199.0, 200.0, 300.0, 500.0}, Eigen::VectorXd::Zero(n));
  const Term step = recovering_step_term(200.0, 100.0);
  const Eigen::MatrixXd x = at.columns(step);
  ASSERT_EQ(x.cols(), 2);
  EXPECT_EQ(step->column_names(), (std::vector<std::string>{"bias_step", "bias_step_recovery"}));
  const std::vector<double> jump{0, 0, 0, 1, 1, 1}, recovery{0, 0, 0, 1, std::exp(-1.0), std::exp(-3.0)};
  for (Eigen::Index k = 0; k < n; ++k) {
    EXPECT_EQ(x(k, 0), jump[static_cast<std::size_t>(k)]) << k;
    EXPECT_NEAR(x(k, 1), recovery[static_cast<std::size_t>(k)], 1e-15) << k;
  }
  EXPECT_LT((at.columns(Term::from_json(step.to_json())) - x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(step.with_parameter(300.0).to_json().at("recovery_tau_s").get<double>(), 100.0);
  EXPECT_EQ(change_term(200.0, false).size(), 1);
  EXPECT_THROW(ChangeTerm(200.0, true, 100.0), Error);
  // A curved trend: (t - t_s) / 1 h and its square from t_s on.
  const Term curved = curved_ramp_term(200.0);
  const Eigen::MatrixXd c = at.columns(Term::from_json(curved.to_json()));
  ASSERT_EQ(c.cols(), 2);
  EXPECT_NEAR(c(5, 0), 300.0 / 3600.0, 1e-15);
  EXPECT_NEAR(c(5, 1), (300.0 / 3600.0) * (300.0 / 3600.0), 1e-15);
  EXPECT_EQ(c(2, 1), 0.0);
  EXPECT_THROW(ChangeTerm(200.0, false, 0.0, true), Error);
}

// Ageing that slows is (tau / 1 h) ln(1 + (t - t0) / tau): its slope at t0 is 1 per hour, it tends to the
// linear ageing (t - t0) / 1 h as tau grows, and the model file keeps tau.
TEST(PhysicsTerms, SlowingAgeingIsLogarithmicAndTendsToTheLinearOne) {
  const TermsAtRest at({100.0, 1000.0, 3700.0, 7300.0}, Eigen::VectorXd::Zero(4));
  const Term slowing = aging_term(3600.0);
  EXPECT_EQ(slowing->kind(), "aging_log");
  const Eigen::MatrixXd x = at.columns(slowing);
  EXPECT_EQ(x(0, 0), 0.0);
  EXPECT_NEAR(x(2, 0), std::log(2.0), 1e-15);  // an hour after t0, with tau an hour
  EXPECT_NEAR(x(3, 0), std::log(3.0), 1e-15);
  const Eigen::MatrixXd linear = at.columns(aging_term()), far = at.columns(aging_term(3.6e9));
  EXPECT_NEAR(linear(3, 0), 2.0, 1e-15);
  EXPECT_LT((far - linear).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_LT((at.columns(Term::from_json(slowing.to_json())) - x).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(aging_term()->kind(), "aging");
}

// Shupe's gradient form is the rate of the coil temperature through a first-order lag of tau: on a ramp of
// r C/s from t = 0 it is r (1 - exp(-t / tau)) - the gradient (T - L) / tau building up to the rate - and the
// rate form is its limit for tau -> 0; the model file keeps tau.
TEST(PhysicsTerms, ShupesGradientFormIsTheRateThroughTheGradientsLag) {
  const Eigen::Index n = 21;
  std::vector<double> t(n);
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = 100.0 * static_cast<double>(k);
  const TermsAtRest at(t, 0.01 * Eigen::Map<const Eigen::VectorXd>(t.data(), n));  // 0.6 C/min
  const Term gradient = shupe_term(400.0);
  const Eigen::MatrixXd x = at.columns(gradient);
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_NEAR(x(k, 0), 0.01 * (1.0 - std::exp(-t[static_cast<std::size_t>(k)] / 400.0)), 1e-12) << k;
  const Eigen::MatrixXd fast = at.columns(shupe_term(1e-3)), rate = at.columns(shupe_term());
  EXPECT_LT((fast - rate).bottomRows(n - 1).cwiseAbs().maxCoeff(), 1e-6);  // 1e-4 of the rate
  EXPECT_LT((at.columns(Term::from_json(gradient.to_json())) - x).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PhysicsTerms, SurfaceBasisReproducesTheBicubicSpline) {
  const std::vector<double> temps{-20, 0, 20, 25, 40, 60}, rates{-100, -40, -10, 10, 40, 100};
  RandomStream rng(5, "surface");
  Eigen::MatrixXd values(6, 6);
  for (Eigen::Index i = 0; i < 36; ++i) values(i) = rng.normal();
  const SplineSurface surface(temps, rates, values, OutsideGridPolicy::clamp);
  Signals s;
  const Eigen::Index n = 200;
  s.t_s.resize(n);
  s.rate.resize(n);
  s.temp_c.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    s.t_s[static_cast<std::size_t>(k)] = static_cast<double>(k);
    s.temp_c(k) = -20 + 80 * rng.uniform();
    s.rate(k) = units::dps_to_radps(-100 + 200 * rng.uniform());
  }
  const Eigen::MatrixXd x = term_columns(scale_factor_surface(temps, rates), s, coil_temperature(s, 0.0), TermScaling::of(s));
  Eigen::VectorXd v(36);
  for (Eigen::Index i = 0; i < 6; ++i)
    for (Eigen::Index j = 0; j < 6; ++j) v(i * 6 + j) = values(i, j);
  const Eigen::VectorXd got = x * v;
  for (Eigen::Index k = 0; k < n; ++k) {
    EXPECT_NEAR(got(k), s.rate(k) * surface(s.temp_c(k), units::radps_to_dps(s.rate(k))).value, 1e-12);
  }
}

TEST(ExplainedModel, CompensationInvertsTheModelAndSurvivesJson) {
  Signals s;
  TermScaling sc;
  sc.t_ref_c = 20, sc.t_scale_c = 40, sc.rate_scale_radps = units::dps_to_radps(100);
  const std::vector<Term> terms{bias_term(), temperature_polynomial({1, 2}), scale_factor_polynomial({{0, 0}, {0, 2}, {1, 0}}),
                                asymmetry_term()};
  Eigen::VectorXd beta(7);
  beta << units::dph_to_radps(-15), units::dph_to_radps(3), units::dph_to_radps(-1), 5e-4, -8e-4, 1e-4, 2e-4;
  const ExplainedModel model(sc, 0.0, terms, beta);
  // Forward: measured = w + e(w) at the true rate w; the model must return e from the measured rate.
  Dataset d;
  d.features = model.features();
  const Eigen::Index n = 50;
  d.x.resize(n, 2);
  d.t_s.resize(n);
  Eigen::VectorXd truth(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    d.t_s[static_cast<std::size_t>(k)] = static_cast<double>(k);
    truth(k) = units::dps_to_radps(-100.0 + 4.0 * static_cast<double>(k));
    Signals one;
    one.t_s = {0.0};
    one.rate = Eigen::VectorXd::Constant(1, truth(k));
    one.temp_c = Eigen::VectorXd::Constant(1, -10.0 + k);
    const double e = (design_matrix(terms, one, coil_temperature(one, 0.0), sc) * beta)(0);
    d.x(k, 0) = truth(k) + e;
    d.x(k, 1) = one.temp_c(0);
  }
  d.measured = d.x.col(0);
  const Eigen::VectorXd compensated = compensate(model, d);
  EXPECT_LT((compensated - truth).cwiseAbs().maxCoeff(), 1e-13);
  const auto back = model_from_json(model.to_json(), "round trip");
  EXPECT_LT((compensate(*back, d) - compensated).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(back->predict(d.x.row(3).data()), model.predict(d.x.row(3).data()), 1e-18);
}

TEST(Explain, NothingMissingGivesNoMissingPhysics) {
  const ExplainResult r = explain_recording(simulate_with("", 11), fast());
  EXPECT_EQ(r.summary.verdict, Verdict::no_missing_physics) << ids(r.summary) << unexplained(r.summary);
  // The residual is the sensor's white noise: 10 deg/h per 1-Hz sample.
  EXPECT_NEAR(r.summary.fit.heldout_rms_after_dph, 10.0, 0.5);
}

TEST(Explain, PlantedShupeIsFoundWithItsCoefficient) {
  const ExplainResult r = explain_recording(simulate_with("shupe_dph_per_c_per_min: 2\n", 12), fast());
  ASSERT_EQ(r.summary.verdict, Verdict::missing_physics);
  const FoundEffect* e = effect(r.summary, "shupe");
  ASSERT_NE(e, nullptr) << ids(r.summary);
  const PhysicalParameter& k = parameter(*e, "k_dph_per_cpm");
  EXPECT_NEAR(k.value, 2.0, 0.2);
  EXPECT_LT(k.low, 2.0);
  EXPECT_GT(k.high, 2.0);
  // Held out, the refitted model is at the noise floor again.
  EXPECT_LT(r.summary.fit.heldout_rms_after_dph, 10.5);
  EXPECT_GT(r.summary.fit.heldout_rms_before_dph, 11.0);
  // Shupe is all of the held-out excess over the white noise: it removes it, to the noise's own scatter.
  ASSERT_TRUE(e->heldout_excess_removed.has_value());
  EXPECT_NEAR(*e->heldout_excess_removed, 1.0, 0.15);
  EXPECT_GT(e->heldout_rms_without_dph, 11.0);
  // explain.json reads back to the same result: written again, the same file (its noise models to round-off).
  const nlohmann::json written = to_json(r.summary);
  const nlohmann::json again = to_json(explain_summary_from_json(nlohmann::json::parse(written.dump())));
  EXPECT_EQ(again["effects"], written["effects"]);
  EXPECT_EQ(again["unexplained"], written["unexplained"]);
  EXPECT_EQ(again["selection"]["steps"], written["selection"]["steps"]);
  EXPECT_EQ(again["fit"], written["fit"]);
  EXPECT_EQ(again["recording"], written["recording"]);
  EXPECT_NEAR(again["noise"]["whitening_model"]["white_sigma"].get<double>(), written["noise"]["whitening_model"]["white_sigma"].get<double>(), 1e-12);
}

// A black-box simulation (explain --model with an RBF calibration): its structure is none of the library's,
// so the baseline family, its form chosen by auto, is refitted beside the network's prediction. A Shupe
// effect the network never saw is named at its coefficient; a recording of the network's own sensor shows
// nothing.
TEST(Explain, ABlackBoxRbfSimulationNamesWhatItsSensorLeftOut) {
  const CalibrationResult fitted = calibrate(simulate_with("", 31), CalibrationRequest{});  // rbf, ols, of the error
  ASSERT_EQ(fitted.model->kind(), "rbf");
  const std::filesystem::path model = std::filesystem::temp_directory_path() / "gyrosid_test_explain_black_box_rbf.json";
  save_model(model, *fitted.model, {});
  ExplainOptions o = fast();
  o.model_path = model.string();
  o.baseline_form = BaselineForm::automatic;
  const ExplainResult r = explain_recording(simulate_with("shupe_dph_per_c_per_min: 2\n", 32), o);
  EXPECT_NE(r.summary.simulation.find("(rbf); the surface's BIC is"), std::string::npos) << r.summary.simulation;
  const FoundEffect* e = effect(r.summary, "shupe");
  ASSERT_NE(e, nullptr) << ids(r.summary);
  EXPECT_NEAR(parameter(*e, "k_dph_per_cpm").value, 2.0, 0.2);  // measured 1.995
  EXPECT_LT(r.summary.fit.heldout_rms_after_dph, 10.5);
  EXPECT_GT(r.summary.fit.heldout_rms_before_dph, 11.0);  // measured 12.0: the effect is there to be left out
  const ExplainResult control = explain_recording(simulate_with("", 33), o);
  EXPECT_EQ(control.summary.verdict, Verdict::no_missing_physics) << ids(control.summary) << unexplained(control.summary);
  std::filesystem::remove(model);
}

// A Shupe bias that follows the coil's gradient rather than its rate: 0.5 deg/h per C of T - L, L the probe
// temperature through a 400-s first-order lag (the core behind the outer layers) - 3.33 (deg/h)/(C/min) of
// dL/dt. On the third generator's gradient Shupe the rate form was named with a thermal lag of 350-390 s
// beside it, lending the rate its delay; the gradient form is Shupe's richer form and names it alone.
TEST(Explain, AShupeBiasThatFollowsTheCoilsGradientIsShupeAlone) {
  Recording rec = simulate_with("", 13);
  const auto& t = rec.column("t_s");
  const auto& temp = rec.column("temp_c");
  const ThermalLagResponse lag = thermal_lag_response({0.0, {400.0}}, PiecewiseLinear{t, temp}, t);
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += 0.5 * (temp[i] - lag.stage[0][i]) / 3600.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  ASSERT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  const FoundEffect* e = effect(r.summary, "shupe");
  ASSERT_NE(e, nullptr) << ids(r.summary);
  EXPECT_NEAR(parameter(*e, "k_dph_per_cpm").value, 0.5 * 400.0 / 60.0, 0.5);
  EXPECT_NEAR(parameter(*e, "gradient_tau_s").value, 400.0, 150.0);
}

TEST(Explain, PlantedThermalLagIsFoundWithItsTimeConstant) {
  // The coil lags the probe by 400 s: every temperature term follows a temperature the probe read earlier.
  SensorSpec sensor = load_sensor(ConfigNode::parse(kSensor, "test sensor"));
  std::get<GyroSensor>(sensor).thermal.coil_tau_s = 400.0;
  const ExplainResult r = explain_recording(simulate_sensor(sensor, 13), fast());
  const FoundEffect* e = effect(r.summary, "thermal_lag");
  ASSERT_NE(e, nullptr) << ids(r.summary);
  EXPECT_NEAR(parameter(*e, "tau_s").value, 400.0, 60.0);
}

// A scale-factor asymmetry beside a flexible baseline (issue 34, class 5). The polynomial FOG with a 300-ppm
// step of its scale factor between the senses (54 deg/h at 100 deg/s, against 10 deg/h of noise): the
// thesis's surface, with nodes at +-10 deg/s and no node at zero, bends to follow |omega| and absorbs it;
// the data do not need the surface, so `auto` takes the polynomial, and the asymmetry is named at its value
// (at 60 ppm the polynomial's omega u^3 absorbs 94 % of it too, and it is listed as absorbed). Forced onto
// the surface, it is listed as what the surface absorbs, with the BIC's preference for the smooth scale
// factor with it and the experiment that would separate the two.
TEST(Explain, AnAsymmetryASurfaceWouldAbsorbIsNamedWhereTheDataDoNotNeedTheSurface) {
  std::string sensor = kSensor;
  const std::string rate_line = "  rate: {coefficients_ppm: [40, 0.6, -0.065]}\n";
  sensor.replace(sensor.find(rate_line), rate_line.size(), rate_line + "  asymmetry_ppm: 300\n");
  const Recording rec = simulate_sensor(load_sensor(ConfigNode::parse(sensor, "asymmetric sensor")), 21);

  ExplainOptions o = fast();
  o.baseline_form = BaselineForm::automatic;
  const ExplainResult chosen = explain_recording(rec, o);
  EXPECT_NE(chosen.summary.simulation.find("polynomial of order 3"), std::string::npos) << chosen.summary.simulation;
  const FoundEffect* e = effect(chosen.summary, "scale_factor_asymmetry");
  std::string why_not;  // on failure: what was demoted or listed as absorbed instead
  for (const auto& d : chosen.summary.demoted) why_not += d.id + " demoted (" + std::to_string(d.delta_bic) + ": " + d.reason + ") ";
  for (const auto& x : chosen.summary.absorbed_alternatives) why_not += x.id + " absorbed (" + x.reason + ") ";
  ASSERT_NE(e, nullptr) << ids(chosen.summary) << why_not;
  const PhysicalParameter& a = parameter(*e, "asymmetry_ppm");
  EXPECT_LT(a.low, 300.0);
  EXPECT_GT(a.high, 300.0);
  EXPECT_NEAR(a.value, 300.0, 45.0);

  o.baseline_form = BaselineForm::surface;
  const ExplainResult forced = explain_recording(rec, o);
  EXPECT_EQ(effect(forced.summary, "scale_factor_asymmetry"), nullptr) << ids(forced.summary);
  const auto& absorbed = forced.summary.absorbed_alternatives;
  const auto it = std::find_if(absorbed.begin(), absorbed.end(), [](const AbsorbedAlternative& x) { return x.id == "scale_factor_asymmetry"; });
  ASSERT_NE(it, absorbed.end());
  EXPECT_EQ(it->absorbed_by, "scale_factor_surface");
  EXPECT_LT(it->delta_bic_full, 10.0);
  EXPECT_GT(it->delta_bic_core, 10.0);
  EXPECT_GT(it->delta_bic_over_flexibility, 10.0);
  EXPECT_NE(it->separating_experiment.find("both senses"), std::string::npos) << it->separating_experiment;
}

// `auto` takes the surface only where the data need it: the polynomial FOG's recording (a scale factor
// quadratic in the rate) keeps the polynomial; the same recording with a scale-factor error of 100 ppm that
// rises and falls between 40 and 80 deg/s (a bump no cubic in the rate follows, but the surface's nodes at
// 40, 60 and 80 deg/s do) takes the surface. Forms given explicitly are kept.
TEST(BaselineForm, AutoTakesTheSurfaceOnlyWhereTheDataNeedIt) {
  const Recording smooth = simulate_with("", 22);
  Recording bumped = smooth;
  std::vector<double> gyro = bumped.column("gyro_dps");
  const std::vector<double>& rate = bumped.column("ref_rate_dps");
  for (std::size_t i = 0; i < gyro.size(); ++i) {
    const double w = rate[i], bump_ppm = std::abs(w) > 40.0 && std::abs(w) < 80.0 ? 100.0 * std::pow(std::sin(units::kPi * (std::abs(w) - 40.0) / 40.0), 2) : 0.0;
    gyro[i] += bump_ppm * 1e-6 * w;
  }
  bumped.set_column("gyro_dps", gyro);
  InputOptions io;
  std::string why;
  EXPECT_EQ(choose_baseline_form(BaselineForm::automatic, load_input(smooth, io), &why), BaselineForm::polynomial) << why;
  EXPECT_NE(why.find("above the polynomial"), std::string::npos) << why;
  EXPECT_EQ(choose_baseline_form(BaselineForm::automatic, load_input(bumped, io), &why), BaselineForm::surface) << why;
  EXPECT_NE(why.find("below the polynomial"), std::string::npos) << why;
  EXPECT_EQ(choose_baseline_form(BaselineForm::surface, load_input(smooth, io), &why), BaselineForm::surface);
  EXPECT_EQ(choose_baseline_form(BaselineForm::polynomial, load_input(bumped, io), &why), BaselineForm::polynomial);
}

// A rate-table recording written here: time (s), reference rate (deg/s), probe temperature (C), gyro (deg/s).
Recording rate_table_recording(const std::string& name, const std::vector<double>& t, const std::vector<double>& rate,
                               const std::vector<double>& probe, const std::vector<double>& gyro) {
  Recording rec(name);
  rec.set_column("t_s", t);
  rec.set_column("ref_rate_dps", rate);
  rec.set_column("temp_c", probe);
  rec.set_column("gyro_dps", gyro);
  return rec;
}

// The rate error (deg/h) of the independent generator's FOG (experiments/concealed_effects/independent.py):
// bias cubic in the coil temperature about 25 C, scale factor quadratic in (T, rate) in ppm, u = rate / 100 deg/s.
double independent_fog_error_dph(double coil_c, double rate_dps) {
  const double d = coil_c - 25.0, u = rate_dps / 100.0;
  const double bias_dph = 8.0 + 0.35 * d - 0.004 * d * d + 5e-5 * d * d * d;
  const double sf_ppm = 150.0 + 4.0 * d - 0.03 * d * d + 25.0 * u - 40.0 * u * u + 0.5 * d * u;
  return bias_dph + sf_ppm * 1e-6 * rate_dps * 3600.0;
}

// A coil lagging the probe by 900 s, on a programme whose held-out cycle reaches coil temperatures the
// training cycles never do (issue 34, class 2), written here from first principles at 0.5 Hz: the FOG of the
// independent generator (experiments/concealed_effects/independent.py: bias cubic in the coil temperature,
// scale factor quadratic in (T, rate), 10 deg/h white noise), the rate a 100 deg/s sine of period 97 s. The
// training cycles spike from 20 to 60 C and back at 8 C/min, so their coil peaks near 35 C; the held-out
// cycle (block 2) soaks an hour at 60 C and cools at 0.5 C/min, so its coil reaches 59 C.
Recording lag_beyond_training_coverage(std::uint64_t seed) {
  const double tau = 900.0, dt = 2.0;
  std::vector<double> knot_t{0.0, 1200.0}, knot_c{20.0, 20.0};
  for (int cycle = 0; cycle < 5; ++cycle) {
    const std::vector<std::pair<double, double>> spike{{300.0, 60.0}, {300.0, 20.0}, {1200.0, 20.0}};
    const std::vector<std::pair<double, double>> soak{{300.0, 60.0}, {3600.0, 60.0}, {4800.0, 20.0}, {1200.0, 20.0}};
    for (const auto& [duration, to] : cycle == 2 ? soak : spike) knot_t.push_back(knot_t.back() + duration), knot_c.push_back(to);
  }
  RandomStream rng(seed, "lag beyond coverage");
  std::vector<double> t, rate, probe, gyro;
  double coil = 20.0;
  std::size_t k = 0;
  for (double s = 0.0; s < knot_t.back(); s += dt) {
    while (knot_t[k + 1] < s) ++k;
    const double p = knot_c[k] + (knot_c[k + 1] - knot_c[k]) * (s - knot_t[k]) / (knot_t[k + 1] - knot_t[k]);
    coil = p + (coil - p) * std::exp(-dt / tau);  // the probe held over the interval
    const double w = 100.0 * std::sin(2.0 * units::kPi * s / 97.0);
    t.push_back(s), rate.push_back(w), probe.push_back(p);
    gyro.push_back(w + (independent_fog_error_dph(coil, w) + 10.0 * rng.normal()) / 3600.0);
  }
  return rate_table_recording("lag beyond the training coverage", t, rate, probe, gyro);
}

// With the lag, every temperature term reads the coil, and the baseline's spline surface has no training
// sample at coil temperatures over 40 C: the lagged model extrapolates on most of the held-out cycle (its
// error there is hundreds of deg/h), though the probe temperatures, which the baseline reads, are covered.
// Scored on the baseline's coverage, the right lag was demoted before the fix (held-out z -29.3, the
// held-out rms left at 21.6 deg/h); scored where neither the baseline nor the lagged model extrapolates, it
// is confirmed (z 8.4) and found at its time constant (862 s, 759-979), and the held-out rms it leaves is
// the noise's (9.93 deg/h).
TEST(Explain, AThermalLagIsJudgedOnTheCoverageOfTheLaggedModel) {
  ExplainOptions o;
  o.selection.bootstrap = 199;
  o.baseline_form = BaselineForm::surface;  // a spline in T is undetermined where no sample is
  const ExplainResult r = explain_recording(lag_beyond_training_coverage(41), o);
  const FoundEffect* e = effect(r.summary, "thermal_lag");
  ASSERT_NE(e, nullptr) << ids(r.summary) << (r.summary.demoted.empty() ? "" : " demoted " + r.summary.demoted.front().reason);
  EXPECT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  const PhysicalParameter& tau = parameter(*e, "tau_s");
  EXPECT_LT(tau.low, 900.0);
  EXPECT_GT(tau.high, 900.0);
  EXPECT_NEAR(tau.value, 900.0, 90.0);
  ASSERT_TRUE(e->heldout_z.has_value());
  EXPECT_GT(*e->heldout_z, 2.0);
  // Most of the held-out cycle is outside the lagged model's support; the rest is at the noise floor.
  EXPECT_GT(r.summary.recording.heldout_outside_support, (r.summary.recording.samples - r.summary.recording.training_samples) / 2);
  EXPECT_LT(r.summary.fit.heldout_rms_after_dph, 10.5);

  // residuals.csv says which rows the held-out proof scored (issue 34, class 6): heldout_scored is 1 exactly
  // on the held-out rows inside the support (heldout 1), 0 on those the tool excluded as extrapolation
  // (heldout 2) and on every training row; their count is the held-out samples less explain.json's
  // heldout_outside_support, and their rms its held-out rms.
  using testing_support::read_json, testing_support::read_text;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "gyrosid_explain_heldout_scored";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_explain_outputs(r, dir);
  const nlohmann::json rec = read_json(dir / "explain.json")["recording"];
  const std::string csv = read_text(dir / "residuals.csv");
  ASSERT_EQ(csv.substr(0, csv.find('\n')), "t_s,residual_before_dph,residual_after_dph,heldout,heldout_scored");
  std::istringstream rows(csv.substr(csv.find('\n') + 1));
  double t = 0.0, before = 0.0, after = 0.0, ss = 0.0;
  int held = 0, scored = 0;
  long n_rows = 0, n_held = 0, n_scored = 0, n_held_unscored = 0;
  char comma = 0;
  while (rows >> t >> comma >> before >> comma >> after >> comma >> held >> comma >> scored) {
    ASSERT_EQ(scored, held == 1 ? 1 : 0) << "t_s " << t << " heldout " << held;
    EXPECT_EQ(held != 0, r.input.heldout[static_cast<std::size_t>(n_rows)] != 0) << "t_s " << t;
    ++n_rows, n_held += held != 0, n_scored += scored, n_held_unscored += held != 0 && scored == 0;
    if (scored) ss += after * after;
  }
  EXPECT_TRUE(rows.eof());
  EXPECT_EQ(n_rows, rec["samples"].get<long>());
  EXPECT_EQ(n_held, rec["samples"].get<long>() - rec["training_samples"].get<long>());
  EXPECT_EQ(n_scored, n_held - rec["heldout_outside_support"].get<long>());
  EXPECT_GT(n_held_unscored, 0);
  EXPECT_GT(n_scored, 0);
  EXPECT_NEAR(std::sqrt(ss / static_cast<double>(n_scored)), r.summary.fit.heldout_rms_after_dph, 1e-6 * r.summary.fit.heldout_rms_after_dph);
  std::filesystem::remove_all(dir);
}

TEST(Explain, AnAuxiliaryChannelOutsideTheLibraryIsReportedAsUnexplained) {
  Recording rec = simulate_with("", 14);
  // A supply voltage wandering slowly; the gyro's bias follows it at 30 deg/h per volt.
  std::vector<double> supply(rec.rows()), gyro = rec.column("gyro_dps");
  const auto& t = rec.column("t_s");
  for (std::size_t i = 0; i < rec.rows(); ++i) {
    supply[i] = 5.0 + 0.3 * std::sin(2 * units::kPi * t[i] / 1700.0) * std::cos(2 * units::kPi * t[i] / 4100.0);
    gyro[i] += 30.0 * (supply[i] - 5.0) / 3600.0;
  }
  rec.set_column("supply_v", supply);
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  bool follows = false;
  for (const auto& u : r.summary.unexplained) follows = follows || (u.channel && *u.channel == "supply_v");
  EXPECT_TRUE(follows) << unexplained(r.summary);
  EXPECT_NE(r.summary.verdict, Verdict::no_missing_physics);
}

// A bias step of 10 deg/h (0.5 sigma: the rms of a mid-record step about its mean is half its size) under
// the sensor's 10 deg/h white noise, half a grid spacing away from every candidate time of the change-point
// grid (D/48 >= 300 s, from 5 % of the record): the gate judges it at its refined time, so it is reported as
// a change point within a minute of the truth, with its size - not taken by a slow Gauss-Markov wander that
// fits a step placed 150 s off better than the step does (issue 12: a 0.5-sigma step was missed so).
TEST(Explain, AHalfSigmaBiasStepBetweenGridTimesIsAChangePointAtItsTime) {
  Recording rec = simulate_with("", 17);
  const auto& t = rec.column("t_s");
  const double duration = t.back() - t.front(), spacing = std::max(300.0, duration / 48.0);
  const double t_step = t.front() + 0.05 * duration + 10.5 * spacing;
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += t[i] >= t_step ? 10.0 / 3600.0 : 0.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  EXPECT_EQ(r.summary.verdict, Verdict::unexplained_residual) << ids(r.summary) << unexplained(r.summary);
  const Unexplained* step = nullptr;
  for (const auto& u : r.summary.unexplained) step = u.kind == UnexplainedKind::change_point ? &u : step;
  ASSERT_NE(step, nullptr) << unexplained(r.summary);
  EXPECT_NEAR(step->t_start_s, t_step, 60.0);
  ASSERT_FALSE(step->parameters.empty());
  EXPECT_NEAR(step->parameters.front().value, 10.0, 2.5);  // +-1 sigma of 1 deg/h about 10
}

// The control: a real slow Gauss-Markov wander (4 deg/h, tau 1200 s: six correlation times in the record)
// added to the same white noise is coloured noise, not a step or a trend - explain finds nothing missing.
TEST(Explain, ASlowGaussMarkovWanderIsNotAChangePoint) {
  Recording rec = simulate_with("", 18);
  const auto& t = rec.column("t_s");
  RandomStream rng(18, "wander");
  const double sd = 4.0, tau = 1200.0;
  std::vector<double> gyro = rec.column("gyro_dps");
  double g = sd * rng.normal();
  for (std::size_t i = 0; i < rec.rows(); ++i) {
    if (i > 0) {
      const double phi = std::exp(-(t[i] - t[i - 1]) / tau);
      g = phi * g + sd * std::sqrt(1.0 - phi * phi) * rng.normal();
    }
    gyro[i] += g / 3600.0;
  }
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  EXPECT_EQ(r.summary.verdict, Verdict::no_missing_physics) << ids(r.summary) << unexplained(r.summary);
  for (const auto& u : r.summary.unexplained) {
    EXPECT_NE(u.kind, UnexplainedKind::change_point);
    EXPECT_NE(u.kind, UnexplainedKind::trend_change);
  }
}

// A rate random walk of K deg/h/sqrt(h) added to the white noise: per-sample increments of sd K / 60 deg/h.
Recording with_random_walk(std::uint64_t seed, double k_dph_per_rt_h) {
  Recording rec = simulate_with("", seed);
  RandomStream rng(seed, "random walk");
  std::vector<double> gyro = rec.column("gyro_dps");
  double b = 0.0;
  for (std::size_t i = 0; i < rec.rows(); ++i) {
    b += k_dph_per_rt_h / 60.0 * rng.normal();
    gyro[i] += b / 3600.0;
  }
  rec.set_column("gyro_dps", gyro);
  return rec;
}

// A 4 deg/h/sqrt(h) random walk (twice the independent generator's control of issue 12, over a record of
// about a third of its length) is coloured noise on every seed: no change point, trend, correlation or cell.
// Without the fix seed 36 gave a change point: the null's noise likelihood stopped in the basin of a long
// Gauss-Markov wander (a slow random walk fits nearly alike), so a step bettered the null only because the
// null's optimum was the wrong one, and the searched change time counted like a regular parameter (ln n).
// (Seeds 37 and 38 are left out: a (T, omega) cell at z 3.98 against 3.61, and a linear ageing trend the
// walk's path resembles, ML dBIC 13.9 - false discoveries this fix does not address.)
TEST(Explain, ARateRandomWalkIsNotAChangePointOnAnySeed) {
  for (std::uint64_t seed : {31, 32, 33, 34, 35, 36}) {
    const ExplainResult r = explain_recording(with_random_walk(seed, 4.0), fast());
    EXPECT_EQ(r.summary.verdict, Verdict::no_missing_physics) << "seed " << seed << ": " << ids(r.summary) << unexplained(r.summary);
  }
}

// The same random walk with a 0.5-sigma bias step (10 deg/h) mid-record: the step is still found, at its time.
TEST(Explain, AHalfSigmaStepOnARandomWalkIsStillFound) {
  Recording rec = with_random_walk(31, 4.0);
  const auto& t = rec.column("t_s");
  const double t_step = t.front() + 0.45 * (t.back() - t.front());
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += t[i] >= t_step ? 10.0 / 3600.0 : 0.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  const Unexplained* step = nullptr;
  for (const auto& u : r.summary.unexplained) step = u.kind == UnexplainedKind::change_point ? &u : step;
  ASSERT_NE(step, nullptr) << ids(r.summary) << unexplained(r.summary);
  EXPECT_NEAR(step->t_start_s, t_step, 120.0);
}

// A trend that sets in partway through (issue 34, class 1) under white noise alone: the whitening of the
// step (the residual of every candidate at once) scores the onset highest (dBIC 644 and 917 here), but the
// null's likelihood noise has already absorbed it as a random walk, and there the onset scored below zero,
// so ranked by that alone it never reached the likelihood comparison. Before the fix seed 43 (10 deg/h per
// hour from 55 % of the record) gave no missing physics with a random walk in the noise, and seed 41 (8 deg/h
// per hour from 30 %) an ageing trend. (These are the two of six recordings - seeds 41-43 at each onset -
// the fix turns; on the other four the onset is not confirmed on the held-out blocks, or an ageing trend
// still wins the likelihood comparison: at about a third of sigma in rms, the power of one recording ends.)
TEST(Explain, AnOnsetTheNullsNoiseAbsorbedCompetesInTheLikelihoodComparison) {
  for (const auto& [seed, at, slope_dph_per_h] : {std::tuple{43, 0.55, 10.0}, std::tuple{41, 0.30, 8.0}}) {
    Recording rec = simulate_with("", static_cast<std::uint64_t>(seed));
    const auto& t = rec.column("t_s");
    const double t_on = t.front() + at * (t.back() - t.front());
    std::vector<double> gyro = rec.column("gyro_dps");
    for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += slope_dph_per_h * std::max(t[i] - t_on, 0.0) / 3600.0 / 3600.0;
    rec.set_column("gyro_dps", gyro);
    const ExplainResult r = explain_recording(rec, fast());
    EXPECT_EQ(r.summary.verdict, Verdict::unexplained_residual) << "seed " << seed << ": " << ids(r.summary) << unexplained(r.summary);
    const Unexplained* onset = nullptr;
    for (const auto& u : r.summary.unexplained) onset = u.kind == UnexplainedKind::trend_change ? &u : onset;
    ASSERT_NE(onset, nullptr) << "seed " << seed << ": " << unexplained(r.summary);
    EXPECT_NEAR(onset->t_start_s, t_on, 300.0) << "seed " << seed;
    for (const auto& term : r.summary.noise.terms) EXPECT_NE(term.id, "rate_random_walk") << "seed " << seed;
  }
}

// A static log at 5 Hz with ADIS16405-like noise (320 deg/h white, a 50 deg/h Gauss-Markov wander of 175 s)
// and a 1,000 deg/h bias step at t_step, 3 h.
Recording static_log_with_step(std::uint64_t seed, double t_step) {
  RandomStream rng(seed, "static log");
  const double rate_hz = 5.0, a = std::exp(-1.0 / (rate_hz * 175.0));
  std::vector<double> t, ref, gyro;
  double wander = 0.0;
  for (int i = 0; i < static_cast<int>(3 * 3600 * rate_hz); ++i) {
    t.push_back(i / rate_hz), ref.push_back(0.0);
    wander = a * wander + 50.0 * std::sqrt(1 - a * a) * rng.normal();
    gyro.push_back((320.0 * rng.normal() + wander + (t.back() >= t_step ? 1000.0 : 0.0)) / 3600.0);
  }
  Recording rec("static.csv");
  rec.set_column("t_s", t), rec.set_column("ref_rate_dps", ref), rec.set_column("gyro_dps", gyro);
  return rec;
}

// A static log's bias step in a Gauss-Markov wander (issue 34, effects in real noise): 3 h at 5 Hz, white
// noise 320 deg/h a sample, a 50 deg/h wander of 175 s (the ADIS16405 x gyros' noise, read in
// experiments/real_recordings) and a 1,000 deg/h step at 6,400 s, 140 s from the nearest time of the
// candidate's grid. The null's noise takes the step as a random walk, and under the whitening that walk
// implies a step scores only within tens of seconds of its time: before the two-window scan located it,
// every seed gave no missing physics with a random walk in the noise. Now the step is found to the sample
// and the final noise has no random walk.
TEST(Explain, AStepInAStaticLogsWanderIsLocatedByTheTwoWindowScan) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const ExplainResult r = explain_recording(static_log_with_step(seed, 6400.0), fast());
    EXPECT_EQ(r.summary.verdict, Verdict::unexplained_residual) << "seed " << seed << ": " << ids(r.summary) << unexplained(r.summary);
    const Unexplained* step = nullptr;
    for (const auto& u : r.summary.unexplained) step = u.kind == UnexplainedKind::change_point ? &u : step;
    ASSERT_NE(step, nullptr) << "seed " << seed << ": " << unexplained(r.summary);
    EXPECT_NEAR(step->t_start_s, 6400.0, 2.0) << "seed " << seed;  // the decimated sample interval is 0.4 s
    for (const auto& term : r.summary.noise.terms) EXPECT_NE(term.id, "rate_random_walk") << "seed " << seed;
  }
}

// The same log with the step inside the first held-out block (the third eighth, 2,700-4,050 s; issue 34,
// class 3): the training rows bracket it, so anywhere in the block fits them alike, and the block's rows
// scored where the search put the step (held-out z -11 on ADIS16405 #1 x with a step planted at 3,488 s):
// it was demoted and nothing reported. Those rows are now outside the step's support; the last held-out
// block confirms its height, and the change is reported as lying in the block.
TEST(Explain, AStepInsideAHeldOutBlockIsReportedAsLyingInThatBlock) {
  for (std::uint64_t seed : {1, 2}) {
    const ExplainResult r = explain_recording(static_log_with_step(seed, 3300.0), fast());
    EXPECT_EQ(r.summary.verdict, Verdict::unexplained_residual) << "seed " << seed << ": " << ids(r.summary) << unexplained(r.summary);
    const Unexplained* step = nullptr;
    for (const auto& u : r.summary.unexplained) step = u.kind == UnexplainedKind::change_point ? &u : step;
    ASSERT_NE(step, nullptr) << "seed " << seed << ": " << unexplained(r.summary);
    EXPECT_NEAR(step->t_start_s, 2700.0, 1.0) << "seed " << seed;
    EXPECT_NEAR(step->t_end_s, 4050.0, 1.0) << "seed " << seed;
  }
}

// A step that partly recovers (issue 34: a hop whose disturbance then relaxes): 20 deg/h at 45 % of the
// record, of which 70 % recovers with a time constant of 1,800 s, under the sensor's 10 deg/h white noise.
// Judged as a pure step it mispredicts every held-out block after it (the third generator's recovering
// steps: dBIC 714-716 in training, held-out z 1.8-1.9, demoted); the step with its recovery, tried before
// the judging, is reported at its time with its height, what lasts and the recovery's time constant.
TEST(Explain, AStepThatPartlyRecoversIsReportedWithItsRecovery) {
  for (std::uint64_t seed : {51, 52}) {
    Recording rec = simulate_with("", seed);
    const auto& t = rec.column("t_s");
    const double t_step = t.front() + 0.45 * (t.back() - t.front());
    std::vector<double> gyro = rec.column("gyro_dps");
    for (std::size_t i = 0; i < rec.rows(); ++i) {
      if (t[i] >= t_step) gyro[i] += 20.0 * (0.3 + 0.7 * std::exp(-(t[i] - t_step) / 1800.0)) / 3600.0;
    }
    rec.set_column("gyro_dps", gyro);
    const ExplainResult r = explain_recording(rec, fast());
    const Unexplained* step = nullptr;
    for (const auto& u : r.summary.unexplained) step = u.kind == UnexplainedKind::change_point ? &u : step;
    ASSERT_NE(step, nullptr) << "seed " << seed << ": " << ids(r.summary) << unexplained(r.summary);
    EXPECT_NEAR(step->t_start_s, t_step, 60.0) << "seed " << seed;
    std::map<std::string, double> p;
    for (const auto& q : step->parameters) p[q.name] = q.value;
    ASSERT_EQ(p.count("recovery_tau_s"), 1u) << "seed " << seed << ": the step was reported without its recovery" << unexplained(r.summary) << " noise " << r.summary.noise.terms.size();
    EXPECT_NEAR(p["step_dph"], 20.0, 4.0) << "seed " << seed;
    EXPECT_NEAR(p["lasting_dph"], 6.0, 3.0) << "seed " << seed;
    EXPECT_GT(p["recovery_tau_s"], 1800.0 / 2) << "seed " << seed;
    EXPECT_LT(p["recovery_tau_s"], 1800.0 * 2) << "seed " << seed;
  }
}

// Two effects at once under coloured noise: a play-operator hysteresis (half-width 1.5 C on the probe
// temperature, heating minus cooling branch 8 deg/h) and an ageing trend (8 deg/h per hour) on a 3 deg/h/rt(h)
// rate random walk. The selection's whitening comes from the residual of every candidate at once, so it is
// nearly white and every slow candidate scores there; the likelihood gate must judge each at the parameter
// its own coloured noise prefers, and take the strongest there. Before the fix the gate judged the
// hysteresis at the width chosen under that near-white whitening and took the first positive candidate in
// its order: on this seed nothing was named (on the independent generator, seed 7051, Shupe was).
TEST(Explain, HysteresisAndAgeingOnARandomWalkAreBothNamedAtTheirParameters) {
  Recording rec = with_random_walk(21, 3.0);
  const auto& t = rec.column("t_s");
  const auto& temp = rec.column("temp_c");
  std::vector<double> gyro = rec.column("gyro_dps");
  const double r = 1.5, offset = 8.0, ageing = 8.0;  // C, deg/h, deg/h per hour
  double play = temp.front();
  for (std::size_t i = 0; i < rec.rows(); ++i) {
    play = std::clamp(play, temp[i] - r, temp[i] + r);
    gyro[i] += (offset * 0.5 * (temp[i] - play) / r + ageing * (t[i] - t.front()) / 3600.0) / 3600.0;
  }
  rec.set_column("gyro_dps", gyro);
  const ExplainResult res = explain_recording(rec, fast());
  ASSERT_EQ(res.summary.verdict, Verdict::missing_physics);
  const FoundEffect* h = effect(res.summary, "thermal_hysteresis");
  const FoundEffect* a = effect(res.summary, "aging_trend");
  ASSERT_NE(h, nullptr) << ids(res.summary);
  ASSERT_NE(a, nullptr) << ids(res.summary);
  EXPECT_EQ(res.summary.effects.size(), 2u) << ids(res.summary);
  const PhysicalParameter& o = parameter(*h, "offset_dph");
  EXPECT_NEAR(o.value, offset, 1.5 * (o.high - o.low) / 2.0);  // within 3 sigma
  EXPECT_NEAR(parameter(*h, "width_c").value, 2.0 * r, 1.0);
  // The walk alone makes a trend over the 2.1-h record uncertain by 3 / 60 / sqrt(7680 s) * 3600 = 2.0 deg/h per
  // hour; the refit's interval (0.42 here) does not include it - it whitens with the selection's near-white model.
  EXPECT_NEAR(parameter(*a, "k_dph_per_h").value, ageing, 2.0 * 2.0);
}

// A loop of two play widths (issue 34, class 4) on a chamber programme with reversals of 4-14 C inside its
// range, written here from first principles at 0.5 Hz (the independent generator's FOG law and 10 deg/h white
// noise; the probe is the coil): widths 2 and 16 C sharing a 20 deg/h loop 35/65. One play of one width
// cannot follow the minor loops' inner shape (on the independent generator it left up to 47 % of such a
// loop's held-out excess and its height 35 % off); the richer form, a second play, must be kept and the
// height and both widths recovered. With widths_c = {2} alone the second play must not be kept.
Recording minor_loops(std::uint64_t seed, const std::vector<double>& widths_c, const std::vector<double>& shares, double height_dph) {
  std::vector<double> knot_t{0.0, 1800.0}, knot_c{20.0, 20.0};
  const std::vector<std::tuple<double, double, double>> segments{  // to C, C/min, hold min
      {50, 1, 20}, {44, 1, 10}, {48, 1, 10}, {40, 1, 10}, {46, 1, 10}, {34, 1, 10}, {42, 1, 10}, {-10, 2, 20},
      {-4, 1, 10}, {-8, 1, 10}, {0, 1, 10}, {-6, 1, 10}, {6, 1, 10}, {0, 1, 10}, {20, 1, 10}};
  for (const auto& [to, rate, hold] : segments) {
    knot_t.push_back(knot_t.back() + std::abs(to - knot_c.back()) / rate * 60.0), knot_c.push_back(to);
    knot_t.push_back(knot_t.back() + hold * 60.0), knot_c.push_back(to);
  }
  RandomStream rng(seed, "minor loops");
  std::vector<double> t, rate, probe, gyro, play(widths_c.size(), knot_c.front());
  std::size_t k = 0;
  for (double s = 0.0; s < knot_t.back(); s += 2.0) {
    while (knot_t[k + 1] < s) ++k;
    const double c = knot_c[k] + (knot_c[k + 1] - knot_c[k]) * (s - knot_t[k]) / (knot_t[k + 1] - knot_t[k]);
    double loop = 0.0;
    for (std::size_t j = 0; j < widths_c.size(); ++j) {
      const double r = 0.5 * widths_c[j];
      play[j] = std::clamp(play[j], c - r, c + r);
      loop += shares[j] * (c - play[j]) / widths_c[j];
    }
    const double w = 100.0 * std::sin(2.0 * units::kPi * s / 97.0);
    t.push_back(s), rate.push_back(w), probe.push_back(c);
    gyro.push_back(w + (independent_fog_error_dph(c, w) + height_dph * loop + 10.0 * rng.normal()) / 3600.0);
  }
  return rate_table_recording("minor loops", t, rate, probe, gyro);
}

TEST(Explain, ALoopOfTwoPlayWidthsIsFittedWithBoth) {
  const ExplainResult two = explain_recording(minor_loops(3, {2.0, 16.0}, {0.35, 0.65}, 20.0), fast());
  const FoundEffect* h = effect(two.summary, "thermal_hysteresis");
  ASSERT_NE(h, nullptr) << ids(two.summary);
  EXPECT_EQ(two.summary.effects.size(), 1u) << ids(two.summary);
  EXPECT_NEAR(parameter(*h, "offset_dph").value, 20.0, 2.0);
  const double narrow = std::min(parameter(*h, "width_c").value, parameter(*h, "second_width_c").value);
  const double wide = std::max(parameter(*h, "width_c").value, parameter(*h, "second_width_c").value);
  EXPECT_NEAR(narrow, 2.0, 1.0);
  EXPECT_NEAR(wide, 16.0, 6.0);
  const double wide_share = parameter(*h, "width_c").value > parameter(*h, "second_width_c").value
                                ? parameter(*h, "offset_dph").value - parameter(*h, "second_offset_dph").value
                                : parameter(*h, "second_offset_dph").value;
  EXPECT_NEAR(wide_share, 0.65 * 20.0, 3.0);

  const ExplainResult one = explain_recording(minor_loops(4, {2.0}, {1.0}, 20.0), fast());
  const FoundEffect* h1 = effect(one.summary, "thermal_hysteresis");
  ASSERT_NE(h1, nullptr) << ids(one.summary);
  EXPECT_NEAR(parameter(*h1, "offset_dph").value, 20.0, 2.0);
  EXPECT_NEAR(parameter(*h1, "width_c").value, 2.0, 0.5);
  for (const auto& p : h1->parameters) EXPECT_NE(p.name, "second_width_c");
}

// Two thermal cycles -20..40 C at 1 C/min with rate cycles, 1 Hz: 240 min, 14,400 samples - long enough for
// a warm-up's slow tail and an ageing trend to differ.
Recording long_recording(std::uint64_t seed, double fast_dph, double fast_tau_s, double slow_dph, double slow_tau_s, double ageing_dph_per_h) {
  std::string trajectory = kTrajectory;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{{"[-40, 40]", "[-20, 40]"},
                                                                                 {"scan_rate_c_per_min: 5", "scan_rate_c_per_min: 1"},
                                                                                 {"temperature_cycles: 4", "temperature_cycles: 2"},
                                                                                 {"rate_limit_c_per_min: 5", "rate_limit_c_per_min: 1"}}) {
    trajectory.replace(trajectory.find(from), from.size(), to);
  }
  Recording rec = simulate(load_sensor(ConfigNode::parse(kSensor, "test sensor")), load_trajectory(ConfigNode::parse(trajectory, "long")), seed).recording;
  const auto& t = rec.column("t_s");
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) {
    const double s = t[i] - t.front();
    gyro[i] += (fast_dph * std::exp(-s / fast_tau_s) + slow_dph * std::exp(-s / slow_tau_s) + ageing_dph_per_h * s / 3600.0) / 3600.0;
  }
  rec.set_column("gyro_dps", gyro);
  return rec;
}

// A warm-up of two time constants (30 deg/h after 600 s and 30 deg/h after 5,000 s: the source and the coil
// settling at their own rates) and nothing else. One exponential cannot follow both; before the fix an
// ageing trend took the slow tail and the warm-up went unnamed. Now an effect selected after the warm-up is
// judged against the warm-up's second time constant (both refitted): the ageing is no better, so it is
// reported as an alternative of the warm-up, not as a finding (the independent generator's 600 s + 2,400 s
// warm-up on lag_hysteresis_warmup seed 7102 had the same ageing beside it).
TEST(Explain, AWarmupsSlowTailIsAnAlternativeNotAnAgeingTrend) {
  const ExplainResult r = explain_recording(long_recording(25, 30.0, 600.0, 30.0, 5000.0, 0.0), fast());
  const FoundEffect* w = effect(r.summary, "warmup_transient");
  ASSERT_NE(w, nullptr) << ids(r.summary);
  EXPECT_EQ(effect(r.summary, "aging_trend"), nullptr) << ids(r.summary);
  EXPECT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  EXPECT_NE(std::find(w->alternatives.begin(), w->alternatives.end(), "aging_trend"), w->alternatives.end());
}

// The control of the rule above: a one-exponential warm-up (40 deg/h, 900 s) and a real ageing trend of
// 4 deg/h per hour - a straight line a second warm-up time constant within the warm-up's range (at most a
// third of the record) cannot follow. Both are named, the trend at its slope.
TEST(Explain, AnAgeingTrendBesideAWarmupIsStillNamed) {
  const ExplainResult r = explain_recording(long_recording(24, 40.0, 900.0, 0.0, 1.0, 4.0), fast());
  ASSERT_NE(effect(r.summary, "warmup_transient"), nullptr) << ids(r.summary);
  const FoundEffect* a = effect(r.summary, "aging_trend");
  ASSERT_NE(a, nullptr) << ids(r.summary);
  EXPECT_NEAR(parameter(*a, "k_dph_per_h").value, 4.0, 1.0);
}

// Ageing that slows, 10 deg/h ln(1 + t / 2,400 s) (a slope of 15 deg/h per hour at the start) over the
// 240-min record: a straight line leaves it curved, and a warm-up's exponential took it on the third
// generator's logarithmic ageing (seed 31410). It is named ageing, at its initial slope and time scale.
TEST(Explain, AgeingThatSlowsIsAgeingNotAWarmup) {
  Recording rec = long_recording(26, 0.0, 1.0, 0.0, 1.0, 0.0);
  const auto& t = rec.column("t_s");
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += 10.0 * std::log1p((t[i] - t.front()) / 2400.0) / 3600.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  ASSERT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  const FoundEffect& a = r.summary.effects[0];
  ASSERT_EQ(a.id, "aging_trend") << ids(r.summary);
  EXPECT_NEAR(parameter(a, "k_dph_per_h").value, 15.0, 5.0);
  EXPECT_GT(parameter(a, "tau_s").value, 2400.0 / 2);
  EXPECT_LT(parameter(a, "tau_s").value, 2400.0 * 2);
}

// A trend of 3 deg/h per hour that sets in at 15 % of the 240-min record (36 min), and nothing else. An
// ageing trend from the first sample explains nearly the same (the onset costs ln n, the misfit of the first
// 36 min about as much): the ageing trend is named with the ramp as its alternative, and the experiment that
// would separate them. On this simulator's noise the step's whitened test already finds the pair redundant;
// on the independent generator's (issue 34: a trend from 15 % of the record, named ageing alone on 3 of 3
// seeds) only the likelihood that chose the ageing trend does, with the pair in
// (experiments/concealed_effects/onsets.py). At 12 deg/h per hour (seed 33) the onset was resolved and the
// trend reported as unexplained, localised in time.
TEST(Explain, ATrendFromEarlyInTheRecordIsAnAlternativeOfAgeing) {
  Recording rec = long_recording(32, 0.0, 1.0, 0.0, 1.0, 0.0);
  const auto& t = rec.column("t_s");
  std::vector<double> gyro = rec.column("gyro_dps");
  const double onset = t.front() + 0.15 * (t.back() - t.front());
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += 3.0 * std::max(0.0, t[i] - onset) / 3600.0 / 3600.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  ASSERT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  const FoundEffect& first = r.summary.effects[0];
  ASSERT_EQ(first.id, "aging_trend") << ids(r.summary);
  EXPECT_NE(std::find(first.alternatives.begin(), first.alternatives.end(), "bias_ramp"), first.alternatives.end());
  ASSERT_FALSE(first.separating.empty());
  EXPECT_NE(first.separating.front().experiment.find("before the supposed onset"), std::string::npos) << first.separating.front().experiment;
}

// A bump of the bias in temperature (a resonance, no polynomial's shape): 30 deg/h at 15 C, 8 C wide, on the
// 10-deg/h noise. The polynomial candidate (dT^4, dT^5 beside the base's cubic) follows it only in part; the
// cubic spline on 8-C knots beside the base's cubic names it and takes the held-out rms back to the noise.
// (At 6 deg/h the polynomial's fit is within the spline's price of its 7 more columns, and it is named in
// polynomial form.)
TEST(Explain, ABumpOfTheBiasInTemperatureIsNamedByTheBiasSpline) {
  Recording rec = simulate_with("", 36);
  const auto& temp = rec.column("temp_c");
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += 30.0 * std::exp(-std::pow((temp[i] - 15.0) / 8.0, 2)) / 3600.0;
  rec.set_column("gyro_dps", gyro);
  const ExplainResult r = explain_recording(rec, fast());
  const FoundEffect* e = effect(r.summary, "temperature_bias");
  ASSERT_NE(e, nullptr) << ids(r.summary) << unexplained(r.summary);
  ASSERT_FALSE(e->parameters.empty());
  EXPECT_EQ(e->parameters.front().name.rfind("b3_", 0), 0u) << "not the spline form: " << e->parameters.front().name;
  EXPECT_EQ(e->parameters.back().name, "knot_spacing_c");
  EXPECT_NEAR(e->parameters.back().value, 8.0, 0.5);
  // Held out, the refitted model is back at the 10-deg/h noise floor.
  EXPECT_LT(r.summary.fit.heldout_rms_after_dph, 10.5);
  EXPECT_GT(r.summary.fit.heldout_rms_before_dph, 11.0);
}

// The test recording (128 min, 8 blocks of 16 min; blocks 2 and 6 held out) with a warm-up of `amplitude_dph`
// decaying with `tau_s` from the first sample added to the gyro output.
Recording with_warmup(std::uint64_t seed, double amplitude_dph, double tau_s) {
  Recording rec = simulate_with("", seed);
  const auto& t = rec.column("t_s");
  std::vector<double> gyro = rec.column("gyro_dps");
  for (std::size_t i = 0; i < rec.rows(); ++i) gyro[i] += amplitude_dph * std::exp(-(t[i] - t.front()) / tau_s) / 3600.0;
  rec.set_column("gyro_dps", gyro);
  return rec;
}

// A warm-up confined to the start of the run (issue 34, class 3): 40 deg/h settling with tau 300 s, under
// 1 % of it left after 1,400 s, 18 % of the record; the first held-out block starts at 1,920 s. The
// held-out blocks hold none of it, so their test measured only the refit's side effects: on this seed the
// effect was demoted at held-out z 1.73 despite dBIC 193 (surface baseline). It is now tested on its own
// support (the first ~700 s) by blocked cross-validation: confirmed (z 6.5), named at its amplitude and time
// constant, with no held-out z (the blocks do not test it). The same recording without it names nothing.
TEST(Explain, AWarmupAtTheStartOfTheRunIsConfirmedOnItsOwnSupport) {
  ExplainOptions o;
  o.selection.bootstrap = 199;
  o.baseline_form = BaselineForm::surface;
  const ExplainResult r = explain_recording(with_warmup(6, 40.0, 300.0), o);
  const FoundEffect* w = effect(r.summary, "warmup_transient");
  ASSERT_NE(w, nullptr) << ids(r.summary) << (r.summary.demoted.empty() ? "" : " demoted " + r.summary.demoted.front().reason);
  EXPECT_EQ(r.summary.effects.size(), 1u) << ids(r.summary);
  EXPECT_NEAR(parameter(*w, "amplitude_dph").value, 40.0, 6.0);
  const PhysicalParameter& tau = parameter(*w, "tau_s");
  EXPECT_NEAR(tau.value, 300.0, 45.0);
  EXPECT_LT(tau.low, 300.0);
  EXPECT_GT(tau.high, 300.0);
  ASSERT_TRUE(w->support_z.has_value());
  EXPECT_GT(*w->support_z, 2.0);
  EXPECT_FALSE(w->heldout_z.has_value());
  // explain.json carries it and reads back to the same effects.
  const nlohmann::json written = to_json(r.summary);
  EXPECT_EQ(written["effects"][0]["support_z"].get<double>(), *w->support_z);
  EXPECT_EQ(to_json(explain_summary_from_json(nlohmann::json::parse(written.dump())))["effects"], written["effects"]);

  const ExplainResult control = explain_recording(simulate_with("", 6), o);
  EXPECT_EQ(control.summary.verdict, Verdict::no_missing_physics) << ids(control.summary);
  EXPECT_EQ(effect(control.summary, "warmup_transient"), nullptr);
}

TEST(Explain, ShupeFromOneRampRateWithoutLagIsReportedWithItsAmbiguity) {
  // No thermal lag and a zig-zag at one ramp rate: dT/dt is +-5 C/min on every sample but the few at each
  // turnaround, so a Shupe bias (k dT/dt; here 2.5 deg/h, a quarter of the noise) and a heating/cooling offset
  // (hysteresis) are the same signal to within a BIC of about 1. The finder must name the planted effect or
  // its twin and list the other as an alternative - never one of them alone. (At k = 2 the turnaround samples
  // alone favour Shupe by a BIC of about 10, and hysteresis is reported as a weaker alternative instead.)
  SensorSpec sensor = load_sensor(ConfigNode::parse(std::string(kSensor) + "shupe_dph_per_c_per_min: 0.5\n", "test sensor"));
  std::get<GyroSensor>(sensor).thermal.tau_s = 0.0;  // the probe follows the chamber's zig-zag
  std::get<GyroSensor>(sensor).thermal.coil_tau_s = 0.0;
  const ExplainResult r = explain_recording(simulate_sensor(sensor, 16), fast());
  ASSERT_EQ(r.summary.verdict, Verdict::missing_physics);
  const FoundEffect& first = r.summary.effects[0];
  ASSERT_TRUE(first.id == "shupe" || first.id == "thermal_hysteresis") << ids(r.summary);
  const std::string twin = first.id == "shupe" ? "thermal_hysteresis" : "shupe";
  EXPECT_NE(std::find(first.alternatives.begin(), first.alternatives.end(), twin), first.alternatives.end()) << first.id;
}

TEST(Explain, PlantedCrossAxisCouplingIsFoundWithItsAngle) {
  // A triad where the x gyro's input axis leans 0.2 mrad towards y: it sees 0.2e-3 of the y rate.
  const Recording single = simulate_with("", 15);
  const auto& t = single.column("t_s");
  std::vector<double> wy(single.rows()), wz(single.rows()), gx = single.column("gyro_dps"), gy(single.rows()), gz(single.rows());
  RandomStream rng(15, "other axes");
  for (std::size_t i = 0; i < single.rows(); ++i) {
    wy[i] = 80.0 * std::sin(2 * units::kPi * t[i] / 97.0);
    wz[i] = 60.0 * std::cos(2 * units::kPi * t[i] / 151.0);
    gx[i] += 0.2e-3 * wy[i];
    gy[i] = wy[i] + 10.0 / 3600.0 * rng.normal();
    gz[i] = wz[i] + 10.0 / 3600.0 * rng.normal();
  }
  Recording rec("triad test");
  rec.set_column("t_s", t);
  rec.set_column("ref_rate_x_dps", single.column("ref_rate_dps"));
  rec.set_column("ref_rate_y_dps", wy);
  rec.set_column("ref_rate_z_dps", wz);
  rec.set_column("temp_c", single.column("temp_c"));
  rec.set_column("gyro_x_dps", gx);
  rec.set_column("gyro_y_dps", gy);
  rec.set_column("gyro_z_dps", gz);
  ExplainOptions o = fast();
  o.input.axis = "x";
  const ExplainResult r = explain_recording(rec, o);
  const FoundEffect* e = effect(r.summary, "cross_axis_coupling");
  ASSERT_NE(e, nullptr) << ids(r.summary);
  EXPECT_NEAR(parameter(*e, "k_y_mrad").value, 0.2, 0.02);
  const PhysicalParameter& kz = parameter(*e, "k_z_mrad");  // no coupling planted towards z
  EXPECT_LT(kz.low, 0.0);
  EXPECT_GT(kz.high, 0.0);
  EXPECT_LT(r.summary.fit.heldout_rms_after_dph, 10.5);
}

TEST(Explain, OptionsAndInputsAreValidated) {
  ExplainOptions o = fast();
  o.model_path = "a.json", o.baseline_path = "b.csv";
  EXPECT_THROW(explain_recording(simulate_with("", 1), o), Error);
  o = fast();
  o.effects = "shupe,not_an_effect";
  try {
    explain_recording(simulate_with("", 1), o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not_an_effect"), std::string::npos);
  }
  o = fast();
  o.input.axis = "x";
  EXPECT_THROW(explain_recording(simulate_with("", 1), o), Error);  // not a triad
  o = fast();
  o.selection.likelihood_tries = 0;
  EXPECT_NE(o.validate(), "");
}

}  // namespace
}  // namespace gyrosid::explain
