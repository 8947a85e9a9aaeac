// Criterion of fit: a perfect compensation leaves no error, decomposition is orthonormal, the Monte Carlo
// is deterministic whatever the thread count and stops by the normality test.
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/parallel.h"
#include "core/random.h"
#include "core/units.h"
#include "nav/cof_report.h"
#include "nav/criterion_of_fit.h"
#include "nav/monte_carlo.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid::nav {
namespace {

const FlightTrajectory& short_flight() {
  static const FlightTrajectory f = generate_flight(builtin_flight("short"), 100.0);
  return f;
}

TriadSensor reference_triad() { return as_triad(load_sensor_file("builtin:sensors/open_loop_fog.yaml")); }

TEST(CriterionOfFit, PerfectCompensationLeavesNoErrorAndRawGyrosDo) {
  const CofEvaluator cof(short_flight(), reference_triad(), nullptr, CofOptions{});
  const CofRun truth = cof.run(CompensationMode::truth, false, 1);
  EXPECT_LT(truth.end_error_m, 1e-6);
  const CofRun raw = cof.run(CompensationMode::none, false, 1);
  EXPECT_GT(raw.end_error_m, 1.0);  // tens of deg/h of bias and up to 0.1 deg/s of scale-factor error
  const Eigen::Vector3d parts = cof.decompose(raw.error_ned);
  EXPECT_NEAR(parts.norm(), raw.end_error_m, 1e-9 * raw.end_error_m);
}

// The adjoint gradient of the position error (strapdown_adjoint.h) against central differences of the INS
// itself along smooth rate errors: a bias, a ramp, and a sinusoid on each axis, at 0.2 deg/h - on the
// short flight at 100 Hz and the long one (Schuler loop, unstable vertical channel) over an hour at 10 Hz.
void expect_gradient_agrees(const CofEvaluator& cof, double at_s) {
  const Excitation& ex = cof.excitation();
  std::array<std::vector<double>, 3> reference;
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < ex.size(); ++k) reference[a].push_back(ex.omega_ib_b[k](static_cast<Eigen::Index>(a)));
  }
  const auto gradient = cof.position_error_gradient(reference, at_s);
  const double eps = units::dph_to_radps(0.2);
  for (std::size_t a = 0; a < 3; ++a) {
    for (int shape = 0; shape < 3; ++shape) {
      const auto n = static_cast<Eigen::Index>(gradient[a].cols());
      Eigen::VectorXd d(n);
      for (Eigen::Index k = 0; k < n; ++k) {
        const double x = static_cast<double>(k) / static_cast<double>(n);
        d(k) = shape == 0 ? 1.0 : shape == 1 ? x : std::sin(17.0 * x + 0.3 * static_cast<double>(a));
      }
      auto plus = reference, minus = reference;
      for (Eigen::Index k = 0; k < n; ++k) plus[a][static_cast<std::size_t>(k)] += eps * d(k), minus[a][static_cast<std::size_t>(k)] -= eps * d(k);
      const Eigen::Vector3d differences = (cof.position_error(plus, at_s) - cof.position_error(minus, at_s)) / (2.0 * eps);
      const Eigen::Vector3d adjoint = gradient[a] * d;
      EXPECT_LT((adjoint - differences).norm(), 2e-5 * differences.norm()) << "axis " << a << " shape " << shape << ": adjoint "
                                                                            << adjoint.transpose() << ", differences " << differences.transpose();
    }
  }
}

TEST(CriterionOfFit, AdjointGradientOfThePositionErrorAgreesWithTheInsItself) {
  const CofEvaluator short_cof(short_flight(), reference_triad(), nullptr, CofOptions{});
  expect_gradient_agrees(short_cof, short_cof.duration_s());
  const FlightTrajectory long_flight = generate_flight(builtin_flight("long"), 10.0);
  const CofEvaluator long_cof(long_flight, reference_triad(), nullptr, CofOptions{});
  expect_gradient_agrees(long_cof, 3600.0);
}

TEST(CriterionOfFit, PerfectCompensationUnderAThermalDelayAndMisalignment) {
  // The truth compensation knows the coil temperature and the misalignment: still nothing left.
  TriadSensor t = as_triad(load_sensor_file("builtin:sensors/fog_triad.yaml"));
  CofOptions o;
  o.thermal_delay_s = 3.0;
  o.start_temp_c = -5.0;
  const CofEvaluator cof(short_flight(), t, nullptr, o);
  EXPECT_LT(cof.run(CompensationMode::truth, false, 1).end_error_m, 1e-6);
}

// The medium flight climbs: with a 300-s delay the coil stays at its start temperature. A model told the
// coil temperature (the gyro's probe, as in the thesis) compensates as well as without the delay; a model
// told the air temperature compensates for temperatures the coil never saw.
TEST(CriterionOfFit, AThermalDelayHurtsOnlyWhenTheModelIsToldTheAirTemperature) {
  const FlightTrajectory f = generate_flight(builtin_flight("medium"), 50.0);
  const TriadSensor t = reference_triad();
  TrajectorySpec dual = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  dual.sampling = Sampling{1111, 0.0};
  const Simulation train = simulate(without_noise(load_sensor_file("builtin:sensors/open_loop_fog.yaml")), dual, 1);
  const CalibrationResult fit = calibrate(train.recording, CalibrationRequest{});  // OLS RBF, ~0.07 deg/h
  const CalibrationModel* model = fit.model.get();
  CofOptions coil, air;
  coil.thermal_delay_s = air.thermal_delay_s = 300.0;
  air.probe = TemperatureProbe::air;
  const double with_coil = CofEvaluator(f, t, model, coil).run(CompensationMode::model, false, 1).end_error_m;
  const double with_air = CofEvaluator(f, t, model, air).run(CompensationMode::model, false, 1).end_error_m;
  const double no_delay = CofEvaluator(f, t, model, CofOptions{}).run(CompensationMode::model, false, 1).end_error_m;
  EXPECT_GT(with_air, 30.0 * with_coil);
  EXPECT_LT(with_coil, 3.0 * no_delay);
}

TEST(CriterionOfFit, RatesAreClippedToTheCalibratedRange) {
  const CofEvaluator cof(short_flight(), reference_triad(), nullptr, CofOptions{});
  EXPECT_GT(cof.max_abs_rate_dps(), 100.0);  // the turn-around and the roll exceed it
  EXPECT_GT(cof.clipped_samples(), 0u);
  CofOptions none;
  none.clip_rate_dps = 0;
  EXPECT_EQ(CofEvaluator(short_flight(), reference_triad(), nullptr, none).clipped_samples(), 0u);
}

TEST(CriterionOfFit, TemperatureFollowsTheLapseRate) {
  const FlightTrajectory f = generate_flight(builtin_flight("medium"), 50.0);
  CofOptions o;
  o.start_temp_c = 10.0;
  const CofEvaluator cof(f, reference_triad(), nullptr, o);
  const double dh = f.truth.back().h - f.truth.front().h;
  EXPECT_GT(std::abs(dh), 100.0);
  EXPECT_NEAR(cof.air_temperature_c().back(), 10.0 - 0.0065 * dh, 1e-9);
}

TEST(MonteCarlo, DeterministicWhateverTheThreadCountAndStopsByNormality) {
  const CofEvaluator cof(short_flight(), reference_triad(), nullptr, CofOptions{});
  auto sample = [&](int i) { return cof.decompose(cof.run(CompensationMode::truth, true, 1000 + static_cast<std::uint64_t>(i)).error_ned); };
  MonteCarloOptions o;
  o.runs = 0;
  o.min_runs = 25;
  o.max_runs = 400;
  setenv("GYROSID_THREADS", "1", 1);
  const MonteCarloResult one = monte_carlo(sample, o);
  setenv("GYROSID_THREADS", "2", 1);
  const MonteCarloResult two = monte_carlo(sample, o);
  unsetenv("GYROSID_THREADS");
  ASSERT_EQ(one.samples.size(), two.samples.size());
  for (std::size_t i = 0; i < one.samples.size(); ++i) EXPECT_EQ(one.samples[i], two.samples[i]);
  // White noise through a perfect compensation: normal errors, accepted early.
  EXPECT_TRUE(one.normal);
  EXPECT_GE(one.runs, 25);
  EXPECT_LT(one.runs, 400);
  EXPECT_NEAR(one.sigma_m, std::sqrt(one.components[0].sigma * one.components[0].sigma +
                                     one.components[1].sigma * one.components[1].sigma +
                                     one.components[2].sigma * one.components[2].sigma), 1e-12);
}

// The automatic stop tests normality at fixed counts (25, 33, 41, ...), not at batch ends, so the number of
// runs does not depend on the batch size (which grows with the threads); a run resumed from saved samples
// ends where the uninterrupted one did.
TEST(MonteCarlo, StopsAtTheSameRunWhateverTheBatchAndResumesIdentically) {
  // Normal errors with a few gross outliers early on: normality is accepted only once they are diluted.
  auto sample = [](int i) {
    RandomStream r(77, "mc/" + std::to_string(i));
    Eigen::Vector3d e(r.normal(), r.normal(), r.normal());
    if (i % 6 == 0 && i < 30) e *= 3.5;
    return e;
  };
  MonteCarloOptions o;
  o.runs = 0;
  o.min_runs = 25;
  o.max_runs = 2000;
  set_worker_threads(1);
  const MonteCarloResult narrow = monte_carlo(sample, o);
  set_worker_threads(7);  // batches of 28
  const MonteCarloResult wide = monte_carlo(sample, o);
  set_worker_threads(0);
  ASSERT_TRUE(narrow.normal);
  EXPECT_GT(narrow.runs, 25);  // not accepted at the first check: the schedule is exercised
  EXPECT_EQ((narrow.runs - 25) % kCheckEvery, 0);
  EXPECT_EQ(narrow.runs, wide.runs) << "narrow " << narrow.runs;
  RecordProperty("runs", narrow.runs);
  EXPECT_EQ(narrow.sigma_m, wide.sigma_m);
  MonteCarloResume resume;
  resume.done.assign(narrow.samples.begin(), narrow.samples.begin() + 30);
  int batches = 0;
  resume.on_batch = [&](const std::vector<Eigen::Vector3d>& all) {
    ++batches;
    EXPECT_GT(all.size(), 30u);
  };
  const MonteCarloResult resumed = monte_carlo(sample, o, resume);
  EXPECT_EQ(resumed.runs, narrow.runs);
  EXPECT_EQ(resumed.sigma_m, narrow.sigma_m);
  EXPECT_GE(batches, narrow.runs > 30 ? 1 : 0);
}

TEST(MonteCarlo, TruthCompensatedNoiseMatchesTheJustNoiseReference) {
  // Compensating perfectly leaves only the sensor's white noise: statistically the thesis's "just noise"
  // reference (same 1-Hz sigma on the reference rates). Compare the spreads from 200 runs each.
  const TriadSensor t = reference_triad();
  const CofEvaluator cof(short_flight(), t, nullptr, CofOptions{});
  MonteCarloOptions o;
  o.runs = 200;
  const MonteCarloResult compensated =
      monte_carlo([&](int i) { return cof.decompose(cof.run(CompensationMode::truth, true, 7 + static_cast<std::uint64_t>(i)).error_ned); }, o);
  const MonteCarloResult noise = monte_carlo(
      [&](int i) { return cof.decompose(cof.run_reference(t.gyros[0].noise.arw_rad_rt_s, 0.0, 9 + static_cast<std::uint64_t>(i)).error_ned); }, o);
  EXPECT_NEAR(compensated.sigma_m / noise.sigma_m, 1.0, 0.2);  // two 200-run estimates of one sigma
}

}  // namespace
}  // namespace gyrosid::nav
