// Triad estimation (solvers/triad): planted misalignment, biases and surfaces recovered from triads simulated
// along Table 2.1 sequences; interval coverage under white noise; entries the data cannot determine reported
// as such; the three back-ends agreeing; known-angle (integral) rows equal to rate rows; the model file and
// the exact compensation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/units.h"
#include "model/classical_model.h"
#include "model/rbf_network.h"
#include "model/triad_model.h"
#include "sim/simulate.h"
#include "solvers/triad/triad_fit.h"
#include "solvers/triad/triad_file.h"
#include "solvers/hand_turn_session.h"
#include "trajectory/calibration_trajectories.h"

namespace gyrosid {
namespace {

using namespace units;

// Six positions, static then turning at 10 deg/s, at the plateaus given.
TrajectorySpec six_positions(std::vector<double> plateaus, double dwell_s, double settle_min) {
  SoakOptions o;
  o.plateaus_c = std::move(plateaus);
  o.settle_min = settle_min;
  o.rates_radps = {0.0, dps_to_radps(10.0)};
  o.step_dwell_s = dwell_s;
  TrajectorySpec t;
  t.profile = classical_soak(o);
  t.profile.latitude_rad = deg_to_rad(-26.2);
  t.sampling.rate_hz = 1.0;
  return t;
}

TriadSensor planted_triad(double white_dph_1hz) {
  TriadSensor t;
  t.name = "planted";
  t.alignment = {GyroAlignment{0.8e-3, -0.5e-3, 0.3e-3, 0.4e-3}, GyroAlignment{-0.6e-3, 0.9e-3, -0.2e-3, 0.5e-3},
                 GyroAlignment{0.4e-3, 0.7e-3, 0.6e-3, -0.3e-3}};
  const double bias_dph[] = {-15.0, 7.0, 22.0};
  for (int i = 0; i < 3; ++i) {
    GyroErrorModel& e = t.gyros[static_cast<std::size_t>(i)].errors;
    e.bias_radps = dph_to_radps(bias_dph[i]);
    e.bias_temperature_radps = Polynomial{{0.0, dph_to_radps(0.1 * (i + 1)), dph_to_radps(-0.002)}, 25.0};
    t.gyros[static_cast<std::size_t>(i)].noise.arw_rad_rt_s = dph_to_radps(white_dph_1hz);
  }
  return t;
}

TriadData simulate_triad_data(const TriadSensor& sensor, const TrajectorySpec& trajectory, std::uint64_t seed) {
  return make_triad_data(simulate(sensor, trajectory, seed).recording);
}

Eigen::Matrix3d true_m(const TriadSensor& t) { return measurement_matrix(t.alignment) - Eigen::Matrix3d::Identity(); }

// The largest error of the misalignment angles (the off-diagonal entries), rad.
double max_off_diagonal_error(const Eigen::Matrix3d& estimate, const Eigen::Matrix3d& truth) {
  Eigen::Matrix3d e = (estimate - truth).cwiseAbs();
  e.diagonal().setZero();
  return e.maxCoeff();
}

// A triad's outputs (rad/s) one per second at 25 C on every gyro, no reference yet.
TriadData triad_at_outputs(const std::vector<Eigen::Vector3d>& outputs) {
  TriadData d;
  const auto n = static_cast<Eigen::Index>(outputs.size());
  d.gyro.resize(n, 3);
  d.temp_c = Eigen::MatrixX3d::Constant(n, 3, 25.0);
  for (Eigen::Index k = 0; k < n; ++k) {
    d.t_s.push_back(static_cast<double>(k));
    d.gyro.row(k) = outputs[static_cast<std::size_t>(k)].transpose();
  }
  return d;
}

// The same data fitted jointly and sequentially, with otherwise the same options.
struct JointAndSequential {
  TriadFit joint, sequential;
};
JointAndSequential fit_both_ways(const TriadData& d, TriadFitOptions o) {
  o.estimation = "joint";
  TriadFit joint = fit_triad(d, o);
  o.estimation = "sequential";
  return {std::move(joint), fit_triad(d, o)};
}

TEST(TriadFit, NoiseFreeMisalignmentAndBiasPolynomialsAreRecoveredExactly) {
  const TriadSensor sensor = planted_triad(0.0);
  const TriadData d = simulate_triad_data(sensor, six_positions({0, 25, 50}, 30, 10), 1);
  TriadFitOptions o;
  o.bias_order = 2;
  const TriadFit f = fit_triad(d, o);
  EXPECT_LT((f.model.misalignment - true_m(sensor)).cwiseAbs().maxCoeff(), 1e-10);
  for (int i = 0; i < 3; ++i) {
    for (double temp : {0.0, 13.0, 25.0, 50.0}) {
      const double truth = sensor.gyros[static_cast<std::size_t>(i)].errors.bias_radps + sensor.gyros[static_cast<std::size_t>(i)].errors.bias_temperature_radps(temp);
      EXPECT_NEAR(radps_to_dph(f.model.bias.at(i, temp)), radps_to_dph(truth), 1e-7) << i << " at " << temp;
    }
    EXPECT_LT(f.residual_rms_dph[static_cast<std::size_t>(i)], 1e-6);
  }
  for (const auto& c : f.angles.combinations) EXPECT_TRUE(c.observable) << c.entry;
  for (bool alone : f.angles.angle_observable) EXPECT_FALSE(alone);
  EXPECT_EQ(f.angles.rank, 6);
}

TEST(TriadFit, IntervalsCoverThePlantedMatrixAtTheirNominalRateUnderWhiteNoise) {
  const TriadSensor sensor = planted_triad(10.0);
  const TrajectorySpec traj = six_positions({25}, 120, 2);
  const Eigen::Matrix3d truth = true_m(sensor);
  std::vector<double> z;
  double sigma_sum = 0.0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    TriadFitOptions o;
    o.bias_order = 0;
    const TriadFit f = fit_triad(simulate_triad_data(sensor, traj, seed), o);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (i == j) continue;
        z.push_back((f.model.misalignment(i, j) - truth(i, j)) / f.uncertainty.misalignment_sigma(i, j));
        sigma_sum += f.uncertainty.misalignment_sigma(i, j);
      }
  }
  double mean = 0.0, var = 0.0;
  for (double v : z) mean += v / static_cast<double>(z.size());
  for (double v : z) var += (v - mean) * (v - mean) / static_cast<double>(z.size() - 1);
  EXPECT_LT(std::abs(mean), 0.25);
  EXPECT_GT(std::sqrt(var), 0.8);
  EXPECT_LT(std::sqrt(var), 1.2);
  // The noise floor: two 120-s turns about each axis at 10 deg/s, N = 10 deg/h at 1 Hz.
  const double floor = dph_to_radps(10.0) / (dps_to_radps(10.0) * std::sqrt(2.0 * 120.0));
  EXPECT_NEAR(sigma_sum / static_cast<double>(z.size()), floor, 0.1 * floor);
}

TEST(TriadFit, AnAxisNeverTurnedLeavesItsColumnUndeterminedAndReportedAsSuch) {
  TriadData d;
  const int n = 600;
  d.gyro.resize(n, 3);
  d.reference.resize(n, 3);
  d.temp_c = Eigen::MatrixX3d::Constant(n, 3, 25.0);
  for (int k = 0; k < n; ++k) {
    d.t_s.push_back(k);
    const double w = (k / 100) % 3 == 0 ? 0.0 : ((k / 100) % 3 == 1 ? 0.2 : -0.2);
    d.reference.row(k) << ((k / 300) == 0 ? w : 0.0), ((k / 300) == 1 ? w : 0.0), 0.0;  // x, then y; never z
    d.gyro.row(k) = (d.reference.row(k) * (Eigen::Matrix3d::Identity() + 1e-3 * Eigen::Matrix3d::Ones()).transpose());
    d.gyro(k, 0) += 1e-3 * std::sin(k * 0.7);  // some noise, deterministic
    d.gyro(k, 1) += 1e-3 * std::cos(k * 1.3);
    d.gyro(k, 2) += 1e-3 * std::sin(k * 2.1);
  }
  TriadFitOptions o;
  const TriadFit f = fit_triad(d, o);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(f.uncertainty.misalignment_known[static_cast<std::size_t>(i)][2]) << i;
    EXPECT_TRUE(f.uncertainty.misalignment_known[static_cast<std::size_t>(i)][0]) << i;
    EXPECT_EQ(f.model.misalignment(i, 2), 0.0);
  }
  const nlohmann::json j = triad_fit_json(f, {});
  EXPECT_TRUE(j["misalignment"]["matrix"][0][2].is_null());
  EXPECT_TRUE(j["misalignment"]["sigma"][1][2].is_null());
  EXPECT_NEAR(j["misalignment"]["matrix"][1][0].get<double>(), 1e-3, 1e-4);
  for (const auto& c : j["observable"]["angle_combinations"]) {
    const std::string e = c["entry"];
    EXPECT_EQ(c["observable"].get<bool>(), e != "M_xz" && e != "M_yz") << e;
  }
  EXPECT_EQ(j["observable"]["independent_combinations"].get<int>(), 4);
  EXPECT_NE(j["observable"]["notes"].dump().find("bias_order 0"), std::string::npos);
}

TEST(TriadFit, EveryBackEndReachesTheSameJointClassicalSolution) {
  TriadSensor sensor = planted_triad(10.0);
  for (auto& g : sensor.gyros) g.errors.scale_factor_rate = Polynomial{{0.0, 0.0, -3e-3}, 0.0};  // -300 ppm at 10 deg/s squared
  SoakOptions o;
  o.plateaus_c = {10, 40};
  o.settle_min = 2;
  o.rates_radps = {0.0, dps_to_radps(10.0), dps_to_radps(40.0), dps_to_radps(90.0)};
  o.step_dwell_s = 30;
  TrajectorySpec t;
  t.profile = classical_soak(o);
  t.sampling.rate_hz = 1.0;
  const TriadData d = simulate_triad_data(sensor, t, 3);
  std::vector<TriadFit> fits;
  for (std::string solver : {"ceres", "nlopt", "ipopt"}) {
    TriadFitOptions f;
    f.surfaces = "classical";
    f.solver = solver;
    f.bias_order = 1;
    f.surface_options = {{"sf_temperature_order", "1"}, {"sf_rate_order", "3"}};
    if (solver == "nlopt") f.solver_options = {{"max_evaluations", "20000"}};
    fits.push_back(fit_triad(d, f));
  }
  for (std::size_t k = 1; k < fits.size(); ++k) {
    EXPECT_LT((fits[k].model.misalignment - fits[0].model.misalignment).cwiseAbs().maxCoeff(), 1e-8) << k;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(fits[k].model.bias.at(a, 25.0), fits[0].model.bias.at(a, 25.0), 1e-10) << k;
  }
  // Off-diagonals against the plant (joint with the rate-nonlinear surface), within 4 sigma.
  const Eigen::Matrix3d truth = true_m(sensor);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) {
        EXPECT_LT(std::abs(fits[0].model.misalignment(i, j) - truth(i, j)), 4 * fits[0].uncertainty.misalignment_sigma(i, j))
            << i << j;
      }
}

TEST(TriadFit, KnownAnglesAloneDetermineTheSameMatrixAsRates) {
  const TriadSensor sensor = planted_triad(0.0);
  Recording rec = simulate(sensor, six_positions({25}, 60, 0), 1).recording;
  // Ferraris: inside each position_id segment only the integral of the reference is known.
  const auto& id = rec.column("position_id");
  for (const char* axis : {"ref_rate_x_dps", "ref_rate_y_dps", "ref_rate_z_dps"}) {
    std::vector<double> ref = rec.column(axis);
    for (std::size_t b = 0; b < ref.size();) {
      std::size_t e = b;
      double sum = 0.0;
      while (e < ref.size() && id[e] == id[b]) sum += ref[e++];
      for (std::size_t k = b; k < e; ++k) ref[k] = sum / static_cast<double>(e - b);
      b = e;
    }
    rec.set_column(axis, ref);
  }
  rec.set_meta("reference", "angle");
  TriadFitOptions o;
  o.bias_order = 0;
  const TriadFit f = fit_triad(make_triad_data(rec), o, "angle");
  EXPECT_NE(f.reference.find("segments"), std::string::npos);
  EXPECT_LT((f.model.misalignment - true_m(sensor)).cwiseAbs().maxCoeff(), 1e-9);
}

// Ferraris: static holds known sample by sample (reference 0) and hand turns of unknown rate profile known
// only by their 360-degree angle (the recording carries the turn's mean rate).
TEST(TriadFit, HandTurnsKnownByTheirAngleDetermineTheMatrixAndRatesCannot) {
  Eigen::Matrix3d m;
  m << 3e-3, -2e-3, 1e-2, 4e-3, -5e-3, 2e-3, -1e-3, 6e-3, 1e-3;
  const Eigen::Vector3d bias(0.01, -0.02, 0.005);
  TriadData d;
  std::vector<Eigen::Vector3d> true_rate, ref;
  int id = 0;
  const double dt = 0.01;
  for (int seg = 0; seg < 9; ++seg) {
    ++id;
    const int n = 300;
    double shape_sum = 0.0;
    for (int k = 0; k < n; ++k) shape_sum += std::sin(units::kPi * (k + 0.5) / n);
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d w = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero();
      if (seg >= 6) {  // a turn about axis seg - 6: a sine-shaped rate whose samples sum to 2 pi / dt
        w(seg - 6) = 2 * units::kPi / dt * std::sin(units::kPi * (k + 0.5) / n) / shape_sum;
        r(seg - 6) = 2 * units::kPi / (n * dt);
      }
      true_rate.push_back(w);
      ref.push_back(r);
      d.t_s.push_back((static_cast<double>(true_rate.size()) - 1) * dt);
      d.position_id.push_back(id);
    }
  }
  const auto n = static_cast<Eigen::Index>(true_rate.size());
  d.gyro.resize(n, 3);
  d.reference.resize(n, 3);
  d.temp_c = Eigen::MatrixX3d::Constant(n, 3, 20.0);
  for (Eigen::Index k = 0; k < n; ++k) {
    d.gyro.row(k) = ((Eigen::Matrix3d::Identity() + m) * true_rate[static_cast<std::size_t>(k)] + bias).transpose();
    d.reference.row(k) = ref[static_cast<std::size_t>(k)].transpose();
  }
  TriadFitOptions o;
  o.reference = "angle";
  const TriadFit angle = fit_triad(d, o);
  EXPECT_LT((angle.model.misalignment - m).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NE(angle.reference.find("3 turns"), std::string::npos) << angle.reference;
  o.reference = "rate";  // the mean rate taken sample by sample: wrong wherever the hand sped up or slowed
  EXPECT_GT(fit_triad(d, o).residual_rms_dph[0], 1e3);
}

// With turns at one rate only, a cubic rate term looks like M_ii: the surface coefficient is held, M_ii kept.
TEST(TriadFit, ASurfaceCoefficientThatMimicsTheScaleFactorYieldsToIt) {
  TriadSensor sensor = planted_triad(10.0);
  for (auto& g : sensor.gyros) g.errors.scale_factor_rate = Polynomial{{0.0, 0.0, -3e-6 / (units::kDegToRad * units::kDegToRad)}, 0.0};
  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 0;
  o.surface_options = {{"sf_temperature_order", "0"}, {"sf_rate_order", "2"}};
  const TriadFit f = fit_triad(simulate_triad_data(sensor, six_positions({25}, 120, 2), 4), o);
  EXPECT_NE(nlohmann::json(f.notes).dump().find("surface_x_sf_rate_2"), std::string::npos);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(f.model.misalignment(i, i), -300e-6, 5 * f.uncertainty.misalignment_sigma(i, i)) << i;
    EXPECT_LT(f.uncertainty.misalignment_sigma(i, i), 30e-6) << i;
  }
}

// Multi-axis turns and a scale factor that depends on each gyro's own rate (thesis eq 3.72 with a classical
// surface): a sequential fit's M (no surface) absorbs the surface's projection onto the other axes' rates;
// the joint fit poses both together and recovers the planted M exactly.
TEST(TriadFit, JointRecoversTheMatrixWhereARateNonlinearSurfaceBiasesTheSequentialFit) {
  TriadModel m;
  m.misalignment << 2e-4, -1e-3, 3e-3, 8e-4, -5e-4, 1.4e-3, 4e-4, -1e-3, 1e-4;
  m.bias.reference_c = 25.0;
  for (int a = 0; a < 3; ++a) m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::VectorXd::Constant(1, dph_to_radps(10.0 * (a - 1)));
  for (int a = 0; a < 3; ++a) {
    auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
    surface->bias = Eigen::VectorXd::Zero(1);
    surface->sf_temperature = Eigen::VectorXd::Zero(1);
    surface->sf_rate = Eigen::Vector3d(0.0, 4e-4 * (a + 1), -3e-3);  // s(w) = sigma_1 u + sigma_2 u^2, u = w / (1 rad/s)
    m.surfaces[static_cast<std::size_t>(a)] = surface;
  }
  // Outputs along single-axis and diagonal turns at +-20, 60, 120 deg/s, with static holds; the reference is
  // the body rate those outputs imply (the model inverted exactly).
  const std::vector<Eigen::Vector3d> directions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}, {1, -1, 0}, {1, 1, 1}};
  std::vector<Eigen::Vector3d> outputs;
  for (const auto& u : directions)
    for (double rate : {0.0, 20.0, -20.0, 60.0, -60.0, 120.0, -120.0})
      for (int k = 0; k < 10; ++k) outputs.push_back(dps_to_radps(rate) * u.normalized());
  TriadData d = triad_at_outputs(outputs);
  d.reference = m.compensate(d);
  ASSERT_LT((m.predict_outputs(d) - d.gyro).cwiseAbs().maxCoeff(), 1e-15);

  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 0;
  o.surface_options = {{"sf_temperature_order", "0"}, {"sf_rate_order", "2"}};
  // Noise-free, the smoothed outputs (the default) are the recorded ones: both inputs hold the plant exactly.
  for (const std::string input : {"measured", "smoothed"}) {
    o.surface_input = input;
    const auto [joint, sequential] = fit_both_ways(d, o);
    const double joint_err = max_off_diagonal_error(joint.model.misalignment, m.misalignment);
    const double sequential_err = max_off_diagonal_error(sequential.model.misalignment, m.misalignment);
    EXPECT_LT(joint_err, 1e-9) << input;
    EXPECT_GT(sequential_err, 1e-4) << input;  // a tenth of a milliradian and more: the nonlinearity, not noise (there is none)
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(joint.residual_rms_dph[static_cast<std::size_t>(a)], 1e-6) << input << a;
      EXPECT_GT(sequential.residual_rms_dph[static_cast<std::size_t>(a)], 1.0) << input << a;
    }
  }
}

// Errors in variables (triad_fit.h, surface_input). Single-axis turns at 0/10/30/60/100 deg/s: the other
// axes' rate columns are (but for the Earth rate) orthogonal to a gyro's own surface columns, so by
// Frisch-Waugh-Lovell the joint and the sequential least-squares fits give that gyro the same surface. They
// do when the surfaces are fitted at the outputs with their noise averaged down (the default). Fitted at the
// recorded outputs, the surface columns carry the noise the rows fit, the order-6 rate polynomial spends its
// weakly determined combinations on it, and the two fits of the same data part between the training rates;
// the smoothed outputs (noise averaged over each 60-s step) take nearly all of that away.
TEST(TriadFit, SurfacesFittedAtSmoothedOutputsAgreeJointAndSequentialWhereTheProblemsSeparate) {
  const TriadSensor sensor = planted_triad(10.0);
  SoakOptions s;
  s.plateaus_c = {10, 40};
  s.settle_min = 5;
  s.rates_radps = {0.0, dps_to_radps(10.0), dps_to_radps(30.0), dps_to_radps(60.0), dps_to_radps(100.0)};
  s.step_dwell_s = 60;
  TrajectorySpec t;
  t.profile = classical_soak(s);
  t.profile.latitude_rad = deg_to_rad(-26.2);
  t.sampling.rate_hz = 1.0;
  const TriadData d = simulate_triad_data(sensor, t, 5);
  // Outputs between (and at) the training rates, about each axis, at 25 C: the two fits' compensations compared.
  std::vector<Eigen::Vector3d> outputs;
  for (int a = 0; a < 3; ++a)
    for (double rate : {2.0, 5.0, 10.0, 20.0, 45.0, 80.0, -45.0, -80.0}) outputs.push_back(dps_to_radps(rate) * Eigen::Vector3d::Unit(a));
  const TriadData probe = triad_at_outputs(outputs);
  auto largest_difference_dph = [&](const std::string& input) {
    TriadFitOptions o;
    o.surfaces = "classical";
    o.bias_order = 2;
    o.surface_input = input;
    o.surface_options = {{"sf_temperature_order", "1"}, {"sf_rate_order", "6"}, {"sf_cross_order", "0"}};  // the figures below are the separable form's
    o.sequential_scale = "surface";  // the classical fitter's own columns: a noisy g column beside M_ii (see below)
    const auto [joint, sequential] = fit_both_ways(d, o);
    return radps_to_dph((joint.model.compensate(probe) - sequential.model.compensate(probe)).cwiseAbs().maxCoeff());
  };
  // The parting goes with the input noise's variance: averaging each 60-s step's 61 samples (surface_window 30)
  // divides it by 61 (measured here: 1.04 -> 0.016 deg/h).
  const double measured = largest_difference_dph("measured"), smoothed = largest_difference_dph("smoothed");
  EXPECT_GT(measured, 0.1);
  EXPECT_LT(smoothed, measured / 30.0);
  EXPECT_LT(smoothed, 0.03);
}

// Outputs of the planted triad `m` along turns about the axes and five body diagonals at each rate (deg/s) and
// temperature, `repeat` samples each; the reference is the body rate they imply (the model inverted exactly).
TriadData turns_triad(const TriadModel& m, const std::vector<double>& rates, const std::vector<double>& temps, int repeat) {
  const std::vector<Eigen::Vector3d> directions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}, {1, -1, 0}, {1, 1, 1}};
  TriadData d;
  std::vector<std::pair<Eigen::Vector3d, double>> at;
  for (double temp : temps)
    for (const auto& u : directions)
      for (double rate : rates)
        for (int k = 0; k < repeat; ++k) at.emplace_back(dps_to_radps(rate) * u.normalized(), temp);
  const auto n = static_cast<Eigen::Index>(at.size());
  d.gyro.resize(n, 3);
  d.temp_c.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    d.t_s.push_back(static_cast<double>(k));
    d.gyro.row(k) = at[static_cast<std::size_t>(k)].first.transpose();
    d.temp_c.row(k).setConstant(at[static_cast<std::size_t>(k)].second);
  }
  d.reference = m.compensate(d);
  return d;
}

// The planted triad of the RBF tests: M, biases linear in temperature, gyro a's scale factor
// s(w) = sigma_1 u + sigma_2 u^2 (u = w / (1 rad/s)) with (sigma_1, sigma_2) = sf_rate(a).
template <class SfRate>
TriadModel planted_rbf_triad(SfRate sf_rate) {
  TriadModel m;
  m.misalignment << 2e-4, -1e-3, 3e-3, 8e-4, -5e-4, 1.4e-3, 4e-4, -1e-3, 1e-4;
  m.bias.reference_c = 25.0;
  m.bias.scale_c = 25.0;
  for (int a = 0; a < 3; ++a) {
    m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::Vector2d(dph_to_radps(10.0 * (a - 1)), dph_to_radps(3.0));
    auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
    surface->bias = Eigen::VectorXd::Zero(1);
    surface->sf_temperature = Eigen::VectorXd::Zero(1);
    const Eigen::Vector2d s = sf_rate(a);
    surface->sf_rate = Eigen::Vector3d(0.0, s(0), s(1));
    m.surfaces[static_cast<std::size_t>(a)] = surface;
  }
  return m;
}

// A FOG-like scale factor that falls with the rate squared, the same on every gyro: s = -3e-4 w^2 (w in rad/s:
// -1300 ppm at 120 deg/s, 0 at rest).
TriadModel fog_like_rbf_triad() { return planted_rbf_triad([](int) { return Eigen::Vector2d(0.0, -3e-4); }); }

// Their training: turns at -120..120 deg/s by 10 at 0, 25 and 50 C, 4 samples each, 10 deg/h white noise; and
// their fit options (RBF surfaces, BIC-selected width-0.3 nodes).
TriadData noisy_turns_training(const TriadModel& m, unsigned seed) {
  std::vector<double> rates;
  for (int r = -120; r <= 120; r += 10) rates.push_back(r);
  TriadData train = turns_triad(m, rates, {0.0, 25.0, 50.0}, 4);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, dph_to_radps(10.0));
  for (Eigen::Index k = 0; k < train.gyro.size(); ++k) train.gyro.data()[k] += noise(rng);
  return train;
}
TriadFitOptions rbf_surface_fit() {
  TriadFitOptions o;
  o.surfaces = "rbf";
  o.bias_order = 1;
  o.surface_options = {{"criterion", "bic"}, {"width", "0.3"}};
  return o;
}

// Compensation error (deg/h rms) of a fit at rates between the training ones, at the training temperatures
// (width-0.3 nodes do not bridge 25 C gaps).
double between_rates_rms_dph(const TriadFit& f, const TriadModel& m) {
  const TriadData probe = turns_triad(m, {0.0, 35.0, -35.0, 75.0, -75.0, 105.0, -105.0}, {0.0, 25.0, 50.0}, 1);
  return radps_to_dph(std::sqrt((f.model.compensate(probe) - probe.reference).squaredNorm() / static_cast<double>(probe.gyro.size())));
}

// RBF surfaces, fitted jointly (rbf_joint=weights): the sequential fit's nodes - its centres and widths, the
// structure its criterion chose - kept, their weights moved with M and b, the surfaces kept out of the columns
// of M_ii and b_i. Planted: M, biases linear in temperature, a rate-nonlinear scale factor (the RBF's job),
// white noise, single-axis and diagonal turns. The joint fit starts at the sequential solution and ends below
// its cost, removes the misalignment bias the nonlinearity leaves in the sequential M, and reproduces the
// planted errors at rates it was not trained on.
TEST(TriadFit, JointRbfWeightsRefineTheSequentialFitAndRecoverThePlantedTriad) {
  const TriadModel m = planted_rbf_triad([](int a) { return Eigen::Vector2d(2e-4 * (a + 1), -1e-3); });
  const TriadData train = noisy_turns_training(m, 7);
  TriadFitOptions o = rbf_surface_fit();
  o.rbf_diagonal = "mean";  // (the default) the gauge this test is about; zero_rate: the next test
  const auto [joint, sequential] = fit_both_ways(train, o);

  const double joint_err = max_off_diagonal_error(joint.model.misalignment, m.misalignment);
  const double sequential_err = max_off_diagonal_error(sequential.model.misalignment, m.misalignment);
  EXPECT_LT(joint_err, 2e-5);
  EXPECT_GT(sequential_err, 1e-4);  // the nonlinearity's projection on the other axes' rates
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    EXPECT_LE(joint.residual_rms_dph[ai], sequential.residual_rms_dph[ai]) << a;  // the joint cost cannot rise
    EXPECT_LT(joint.residual_rms_dph[ai], 11.5) << a;                             // near the 10 deg/h noise
    const auto& jn = dynamic_cast<const RbfNetwork&>(*joint.model.surfaces[ai]);
    const auto& sn = dynamic_cast<const RbfNetwork&>(*sequential.model.surfaces[ai]);
    ASSERT_EQ(jn.nodes(), sn.nodes()) << a;
    EXPECT_EQ(jn.centres, sn.centres) << a;
    EXPECT_EQ(jn.widths, sn.widths) << a;
  }
  // Rates between the training ones: the planted errors recovered (deg/h; the surfaces reach 900 deg/h at
  // 105 deg/s).
  EXPECT_LT(between_rates_rms_dph(joint, m), 6.0);
  EXPECT_GT(between_rates_rms_dph(sequential, m), 5.0 * between_rates_rms_dph(joint, m));
  // rbf_bias=held (the default): the bias polynomials are the sequential fit's, its network's constant folded into
  // the constant term, with the sequential fit's sigmas; rbf_bias=free moves them.
  o.rbf_bias = "free";
  const TriadFit joint_free = fit_triad(train, o);
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    Eigen::VectorXd expected = sequential.model.bias.coefficients[ai];
    expected(0) += dynamic_cast<const RbfNetwork&>(*sequential.model.surfaces[ai]).bias;
    EXPECT_TRUE(joint.model.bias.coefficients[ai].isApprox(expected, 1e-12)) << a;
    EXPECT_GT((joint_free.model.bias.coefficients[ai] - expected).cwiseAbs().maxCoeff(), dph_to_radps(1e-3)) << a;
    for (Eigen::Index k = 0; k < expected.size(); ++k) {
      EXPECT_TRUE(joint.uncertainty.bias_known[ai][static_cast<std::size_t>(k)]) << a << k;
      EXPECT_NEAR(joint.uncertainty.bias_sigma[ai](k), sequential.uncertainty.bias_sigma[ai](k), 1e-12) << a << k;
    }
  }
}

// rbf_diagonal=zero_rate: M_ii is the zero-rate scale factor and the surface carries the rate
// dependence. Planted: a FOG-like scale factor that falls with rate^2 (s = -3e-4 w^2, w in rad/s: -1300 ppm at
// 120 deg/s, 0 at rest), so the planted M_ii is the zero-rate gain. The zero-rate gauge recovers it and the
// off-diagonals; the mean gauge reports M_ii shifted by the mean scale factor over the turns.
TEST(TriadFit, ZeroRateGaugeRecoversTheZeroRateScaleFactorBesideAnRbfSurface) {
  const TriadModel m = fog_like_rbf_triad();
  const TriadData train = noisy_turns_training(m, 11);
  TriadFitOptions o = rbf_surface_fit();
  o.rbf_diagonal = "zero_rate";
  const auto [joint, sequential] = fit_both_ways(train, o);
  o.rbf_diagonal = "mean";
  const auto [joint_mean, sequential_mean] = fit_both_ways(train, o);
  for (int i = 0; i < 3; ++i) {
    const double shifted = std::abs(joint_mean.model.misalignment(i, i) - m.misalignment(i, i));
    EXPECT_GT(shifted, 4e-4) << i;  // 558-590 ppm: the mean scale factor over the turns
    // 46-87 ppm (joint), 95-125 ppm (sequential, whose off-diagonals the diagonal turns bias): the gain over
    // the nodes' width near zero rate
    EXPECT_NEAR(joint.model.misalignment(i, i), m.misalignment(i, i), 1e-4) << i;
    EXPECT_LT(std::abs(sequential.model.misalignment(i, i) - m.misalignment(i, i)), 0.4 * shifted) << i;
  }
  EXPECT_LT(max_off_diagonal_error(joint.model.misalignment, m.misalignment), 2e-5);
  // Between the training rates (deg/h): joint 3.75, sequential 11.7 (its off-diagonals, from the stage without
  // surfaces, carry the nonlinearity's projection on the diagonal turns). The mean gauge gives 2.53 here: on
  // this steep law (-1300 ppm at 120 deg/s) the nodes chosen in that gauge hold the added trend less well
  // (on the reference FOG triad, which gauge flies better depends on the programme: triad_fit.h).
  EXPECT_LT(between_rates_rms_dph(joint, m), 5.0);
  EXPECT_LT(between_rates_rms_dph(joint, m), 0.5 * between_rates_rms_dph(sequential, m));
}

// rbf_form=scale_factor: the network is a relative scale-factor error r(T, g), the surface g r - the classical
// surface's form. Planted: the FOG-like law of the last test, s = -3e-4 w^2 (0 at rest), a scale factor proper:
// the gyro's input (its cross terms with it) scaled by 1 + s. An additive network must make the zero-rate gain's
// departure from 1 + M_ii (M_ii: the mean scale factor over the turns, in the default gauge) as a slope at zero
// rate; a relative one makes it as a value, r(T, 0), interpolated between the turns - so the small-signal gain
// (1 + M_ii) / (1 - r(T, 0)) is the planted 1 + M_ii^true in the mean gauge, which the additive network gets
// only in the zero-rate gauge. The joint fit recovers the off-diagonals; the sequential fit (its second stage:
// M_ii, b and the weights with the first stage's off-diagonals held, which the diagonal turns bias) does not.
TEST(TriadFit, ARelativeRbfCarriesTheZeroRateGainAsAValueInTheMeanGauge) {
  const TriadModel m = fog_like_rbf_triad();
  const TriadData train = noisy_turns_training(m, 11);
  TriadFitOptions o = rbf_surface_fit();
  o.rbf_form = "scale_factor";
  const auto [joint, sequential] = fit_both_ways(train, o);
  for (int a = 0; a < 3; ++a) {
    const auto aa = static_cast<std::size_t>(a);
    const auto& net = dynamic_cast<const RbfNetwork&>(*joint.model.surfaces[aa]);
    EXPECT_EQ(net.output_factor, 0) << a;
    EXPECT_EQ(dynamic_cast<const RbfNetwork&>(*sequential.model.surfaces[aa]).output_factor, 0) << a;
    EXPECT_GT(std::abs(joint.model.misalignment(a, a) - m.misalignment(a, a)), 4e-4) << a;  // the mean gauge
    for (double temp : {0.0, 25.0, 50.0}) {
      const double raw[2] = {0.0, temp};
      double xn[2];
      net.normalizer.apply(raw, xn);
      const double gain = (1.0 + joint.model.misalignment(a, a)) / (1.0 - net.evaluate_normalised(xn));
      EXPECT_NEAR(gain, 1.0 + m.misalignment(a, a), 1e-4) << a << " at " << temp << " C";
    }
    EXPECT_LE(joint.residual_rms_dph[aa], sequential.residual_rms_dph[aa]) << a;
  }
  EXPECT_LT(max_off_diagonal_error(joint.model.misalignment, m.misalignment), 2e-5);
  EXPECT_GT(max_off_diagonal_error(sequential.model.misalignment, m.misalignment), 5e-5);
  // Between the training rates (deg/h): joint 4.5, sequential 12.2.
  EXPECT_LT(between_rates_rms_dph(joint, m), 0.5 * between_rates_rms_dph(sequential, m));
}

// Hand turns known by gravity (reference=gravity, solvers/triad/gravity_turns.h): holds at random attitudes,
// turns between them at a constant body rate (so the sampled rotations compose exactly), outputs from a
// planted M (scale factors and misalignment) and biases, specific force from each hold's attitude. Noise-free,
// the fit recovers all nine entries of M and the biases - from the holds' gravity directions alone.
// A triad whose gyros' rate shape moves with temperature, as the reference FOG's does (its rate^2 coefficient
// -(650 + 5 dT + 0.04 dT^2) ppm): classical surfaces with a v u^2 cross term, biases linear in temperature.
TriadModel planted_with_cross_terms() {
  TriadModel m;
  m.misalignment << -3e-4, -1e-3, 3e-3, 8e-4, 2e-4, 1.4e-3, 4e-4, -1e-3, 1e-4;
  m.bias.reference_c = 25.0;
  m.bias.scale_c = 45.0;
  for (int a = 0; a < 3; ++a) m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::Vector2d(dph_to_radps(10.0 * (a - 1)), dph_to_radps(3.0));
  for (int a = 0; a < 3; ++a) {
    auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
    surface->rate_scale = dps_to_radps(100.0);
    surface->temperature_reference = 25.0;
    surface->temperature_scale = 45.0;
    surface->bias = Eigen::VectorXd::Zero(1);
    surface->sf_temperature = Eigen::VectorXd::Zero(1);
    surface->sf_rate = Eigen::Vector4d(0.0, 60e-6 * (a + 1), -650e-6, 25e-6);  // u, u^2, u^3 (u = w / 100 deg/s)
    surface->sf_cross = (Eigen::MatrixXd(1, 3) << 10e-6, -250e-6, 0.0).finished();  // v u, v u^2
    m.surfaces[static_cast<std::size_t>(a)] = surface;
  }
  return m;
}

// Noise-free turns about the given body directions at 0, +-20, +-60, +-100 deg/s and -20/25/70 C: the
// outputs the planted model gives for that reference (g = (I + M) omega + b(T) + e(T, g), solved by fixed-point
// iteration: e's slope is ~1e-3).
TriadData outputs_of(const TriadModel& m, const std::vector<Eigen::Vector3d>& directions) {
  std::vector<Eigen::Vector3d> rates;
  std::vector<double> temps;
  for (double temp : {-20.0, 25.0, 70.0})
    for (const auto& u : directions)
      for (double rate : {0.0, 20.0, -20.0, 60.0, -60.0, 100.0, -100.0})
        for (int k = 0; k < 10; ++k) rates.push_back(dps_to_radps(rate) * u.normalized()), temps.push_back(temp);
  TriadData d = triad_at_outputs(rates);
  for (Eigen::Index k = 0; k < d.size(); ++k) d.temp_c.row(k).setConstant(temps[static_cast<std::size_t>(k)]);
  d.reference = d.gyro;
  for (int it = 0; it < 30; ++it) d.gyro = m.predict_outputs(d);
  EXPECT_LT((m.predict_outputs(d) - d.gyro).cwiseAbs().maxCoeff(), 1e-17);
  return d;
}

TriadFitOptions classical_options(int cross_order) {
  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 1;
  o.surface_options = {{"sf_temperature_order", "1"}, {"sf_rate_order", "3"}, {"sf_cross_order", std::to_string(cross_order)}};
  return o;
}

// The gauge of M_ii (triad_fit.h, sequential_scale). Single-axis turns: nothing couples a gyro's surface to the
// other axes' columns, so once both fits give M_ii the whole constant scale factor (against the reference
// rate) the sequential fit is the joint one (Frisch-Waugh-Lovell) - exactly, even where the surface family
// cannot hold the sensor (separable form, cross term planted). The classical fitter's own constant scale
// factor on the measured output (sequential_scale=surface) weights the residual by (1 - s_0) and so moves the
// misfit elsewhere along the direction M_ii shares with the odd rate powers. With the family that holds the
// sensor, M_ii is recovered exactly by both.
TEST(TriadFit, SequentialWithTheTriadsScaleFactorIsTheJointFitWhereTheProblemsSeparate) {
  const TriadModel m = planted_with_cross_terms();
  const TriadData d = outputs_of(m, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  std::vector<Eigen::Vector3d> between;  // rates between the training ones, at 0 C
  for (int a = 0; a < 3; ++a)
    for (double rate : {5.0, 40.0, -80.0, 90.0}) between.push_back(dps_to_radps(rate) * Eigen::Vector3d::Unit(a));
  TriadData probe = triad_at_outputs(between);
  probe.temp_c.setConstant(0.0);
  auto parting_dph = [&](const TriadFit& a, const TriadFit& b) { return radps_to_dph((a.model.compensate(probe) - b.model.compensate(probe)).cwiseAbs().maxCoeff()); };

  const auto [joint, sequential] = fit_both_ways(d, classical_options(1));  // the family holds the sensor
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(joint.model.misalignment(i, i), m.misalignment(i, i), 1e-10) << i;
    EXPECT_NEAR(sequential.model.misalignment(i, i), m.misalignment(i, i), 1e-10) << i;
  }
  EXPECT_LT(max_off_diagonal_error(joint.model.misalignment, m.misalignment), 1e-10);

  TriadFitOptions o = classical_options(0);  // separable: a misfit of several deg/h left to place
  const auto [joint0, sequential0] = fit_both_ways(d, o);
  EXPECT_GT(joint0.residual_rms_dph[0], 1.0);
  o.estimation = "sequential";
  o.sequential_scale = "surface";
  const TriadFit own_scale = fit_triad(d, o);
  const double same = parting_dph(joint0, sequential0), other = parting_dph(joint0, own_scale);
  // Measured: 1.1e-5 deg/h (the off-diagonals of the sequential first stage, fitted without the surface) against
  // 0.51 deg/h.
  EXPECT_LT(same, 1e-4);
  EXPECT_GT(other, 0.1);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sequential0.model.misalignment(i, i), joint0.model.misalignment(i, i), 1e-10) << i;
    // The surface's own scale factor leaves a residual (1 - s_0) times an output residual: the smaller number.
    EXPECT_LT(own_scale.residual_rms_dph[static_cast<std::size_t>(i)], joint0.residual_rms_dph[static_cast<std::size_t>(i)]) << i;
  }
}

// Turns about one body diagonal besides the single axes (unbalanced): a gyro's own-rate surface projects onto
// the other axes' columns. With a surface family that holds the sensor (cross term) the joint fit recovers the
// planted M exactly and compensates rates it was not trained on exactly; the sequential one (M first, no
// surface) takes the nonlinearity as misalignment. The thesis's separable family leaves a misfit of several
// deg/h between the training rates whichever way it is fitted - what a criterion of fit then rewards is where
// each fit places that misfit (experiments/triad_misalignment/README.md).
TEST(TriadFit, JointRecoversTheTriadOnAnUnbalancedDesignWhenTheSurfaceFamilyHoldsTheSensor) {
  const TriadModel m = planted_with_cross_terms();
  const TriadData d = outputs_of(m, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}});
  const TriadData probe = outputs_of(m, {{1, 0, 0}, {0, 1, 1}, {1, -1, 1}});  // other directions
  const auto [joint, sequential] = fit_both_ways(d, classical_options(1));
  EXPECT_LT(max_off_diagonal_error(joint.model.misalignment, m.misalignment), 1e-10);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(joint.model.misalignment(i, i), m.misalignment(i, i), 1e-10) << i;
  EXPECT_GT(max_off_diagonal_error(sequential.model.misalignment, m.misalignment), 2e-5);  // measured 5.8e-5
  auto error_dph = [&](const TriadFit& f) { return radps_to_dph((f.model.compensate(probe) - probe.reference).cwiseAbs().maxCoeff()); };
  EXPECT_LT(error_dph(joint), 1e-6);
  EXPECT_GT(error_dph(sequential), 1.0);
  const auto [joint0, sequential0] = fit_both_ways(d, classical_options(0));
  EXPECT_GT(error_dph(joint0), 1.0);
  EXPECT_GT(error_dph(sequential0), 1.0);
}

// surface.sf_cross_order=auto: the order chosen by BIC in either mode - the cross term where the planted rate
// shape moves with temperature, the separable form where it does not (10 deg/h white noise, seeded).
TEST(TriadFit, CrossOrderAutoTakesTheCrossTermOnlyWhenTheSensorHasOne) {
  auto chosen = [](bool cross, const std::string& estimation) {
    TriadModel m = planted_with_cross_terms();
    if (!cross)
      for (auto& s : m.surfaces) std::const_pointer_cast<ClassicalModel>(std::dynamic_pointer_cast<const ClassicalModel>(s))->sf_cross.resize(0, 0);
    TriadData d = outputs_of(m, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}});
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0.0, dph_to_radps(10.0));
    for (Eigen::Index k = 0; k < d.gyro.size(); ++k) d.gyro(k) += noise(rng);
    TriadFitOptions o = classical_options(0);
    o.surface_options["sf_cross_order"] = "auto";
    o.estimation = estimation;
    const TriadFit f = fit_triad(d, o);
    EXPECT_EQ(f.summary.details["sf_cross_order_bic"].size(), 4u);
    return std::stoi(f.summary.details["surface_sf_cross_order"].get<std::string>());
  };
  for (const std::string estimation : {"joint", "sequential"}) {
    EXPECT_GE(chosen(true, estimation), 1) << estimation;
    EXPECT_EQ(chosen(false, estimation), 0) << estimation;
  }
  TriadFitOptions rbf;
  rbf.surfaces = "rbf";
  rbf.surface_options = {{"sf_cross_order", "auto"}};
  EXPECT_NE(rbf.validate().find("needs surfaces=classical"), std::string::npos);
}

// `d` with 10 deg/h white noise on every output (seeded).
TriadData with_white_noise(TriadData d, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, dph_to_radps(10.0));
  for (Eigen::Index k = 0; k < d.gyro.size(); ++k) d.gyro(k) += noise(rng);
  return d;
}

// The planted cross-term triad on the one-diagonal design with 10 deg/h white noise (seeded).
TriadData noisy_outputs_of_planted_cross_triad(std::uint64_t seed) {
  return with_white_noise(outputs_of(planted_with_cross_terms(), {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}), seed);
}

// estimation=auto (solvers/triad/auto_estimation.h). Single-axis turns separate M from the surfaces: the two fits'
// M agree (exactly, by Frisch-Waugh-Lovell, where the surface family holds the sensor: T measured 1e-10..3e-9)
// and the test keeps the sequential fit (20 noise draws; at level 0.01 a true restriction is rejected at most that
// often). One body diagonal besides: the sequential M takes the planted rate shape as misalignment (5.8e-5 rad
// noise-free), the test rejects it (T measured 2920 against 21.7) and returns the joint fit.
TEST(TriadFit, AutoEstimationReturnsTheJointFitOnlyWhereTheSurfacesCoupleWithM) {
  const TriadModel m = planted_with_cross_terms();
  TriadFitOptions o = classical_options(1);
  o.estimation = "auto";
  const TriadData balanced = outputs_of(m, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  int rejected = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const TriadFit f = fit_triad(with_white_noise(balanced, seed), o);
    const nlohmann::json& test = f.summary.details["coupling_test"];
    EXPECT_EQ(test["dof"], 9) << seed;
    rejected += test["rejected"].get<bool>() ? 1 : 0;
    EXPECT_EQ(f.summary.details["estimation_chosen"], test["rejected"].get<bool>() ? "joint" : "sequential") << seed;
  }
  EXPECT_LE(rejected, 1);

  const TriadData one_diagonal = noisy_outputs_of_planted_cross_triad(7);
  const TriadFit chosen = fit_triad(one_diagonal, o);
  const auto [joint, sequential] = fit_both_ways(one_diagonal, classical_options(1));
  const nlohmann::json& test = chosen.summary.details["coupling_test"];
  EXPECT_GT(test["statistic"].get<double>(), 10.0 * test["critical"].get<double>());
  EXPECT_EQ(chosen.summary.details["estimation_chosen"], "joint");
  EXPECT_EQ((chosen.model.misalignment - joint.model.misalignment).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(max_off_diagonal_error(joint.model.misalignment, m.misalignment), 0.5 * max_off_diagonal_error(sequential.model.misalignment, m.misalignment));
  // The covariance the test uses carries the reported sigmas on its diagonal, in both modes.
  for (const TriadFit* f : {&joint, &sequential})
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(std::sqrt(f->uncertainty.misalignment_covariance(3 * i + j, 3 * i + j)), f->uncertainty.misalignment_sigma(i, j), 1e-9 * f->uncertainty.misalignment_sigma(i, j)) << i << j;
  // RBF surfaces (their sequential fit is the RBF fitter's, not the triad problem's): the planted rate-nonlinear
  // triad on single-axis and diagonal turns couples the surfaces with M (T measured 8.7e4); auto returns the joint fit.
  const TriadModel rbf_truth = planted_rbf_triad([](int a) { return Eigen::Vector2d(2e-4 * (a + 1), -1e-3); });
  const TriadData rbf_train = noisy_turns_training(rbf_truth, 7);
  TriadFitOptions rbf = rbf_surface_fit();
  rbf.estimation = "auto";
  const TriadFit rbf_auto = fit_triad(rbf_train, rbf);
  rbf.estimation = "joint";
  const TriadFit rbf_joint = fit_triad(rbf_train, rbf);
  EXPECT_EQ(rbf_auto.summary.details["estimation_chosen"], "joint");
  EXPECT_GT(rbf_auto.summary.details["coupling_test"]["statistic"].get<double>(), rbf_auto.summary.details["coupling_test"]["critical"].get<double>());
  EXPECT_EQ((rbf_auto.model.misalignment - rbf_joint.model.misalignment).cwiseAbs().maxCoeff(), 0.0);
  // No entry of M left to compare (every sigma above max_sigma): the joint fit, with the reason.
  TriadFitOptions untestable = o;
  untestable.max_sigma = 1e-12;
  const TriadFit fallback = fit_triad(one_diagonal, untestable);
  EXPECT_EQ(fallback.summary.details["estimation_chosen"], "joint");
  EXPECT_FALSE(fallback.summary.details.contains("coupling_test"));
  EXPECT_NE(fallback.notes.front().find("the test could not be made"), std::string::npos);
  TriadFitOptions bad = o;
  bad.estimation = "both";
  EXPECT_NE(bad.validate().find("estimation must be joint, sequential or auto"), std::string::npos);
  bad.estimation = "auto";
  bad.coupling_test_level = 0.0;
  EXPECT_NE(bad.validate().find("coupling_test_level"), std::string::npos);
}

// The triad's classical surfaces choose their cross order by BIC unless told (surface.sf_cross_order absent =
// auto), in either mode; the single-gyro classical model keeps the thesis's separable form as its default.
TEST(TriadFit, ClassicalSurfacesChooseTheirCrossOrderByDefault) {
  EXPECT_EQ(ClassicalOptions{}.sf_cross_order, 0);
  const TriadData d = noisy_outputs_of_planted_cross_triad(7);
  for (const std::string estimation : {"joint", "sequential"}) {
    TriadFitOptions unset = classical_options(0);
    unset.surface_options.erase("sf_cross_order");
    unset.estimation = estimation;
    TriadFitOptions given = unset;
    given.surface_options["sf_cross_order"] = "auto";
    const TriadFit by_default = fit_triad(d, unset), by_auto = fit_triad(d, given);
    ASSERT_TRUE(by_default.summary.details.contains("sf_cross_order_bic")) << estimation;
    EXPECT_EQ(by_default.summary.details["sf_cross_order_bic"], by_auto.summary.details["sf_cross_order_bic"]) << estimation;
    EXPECT_GE(std::stoi(by_default.summary.details["surface_sf_cross_order"].get<std::string>()), 1) << estimation;  // the planted v u^2
    EXPECT_EQ((by_default.model.misalignment - by_auto.model.misalignment).cwiseAbs().maxCoeff(), 0.0) << estimation;
  }
  // The classical fitter's own form (sequential_scale=surface) refuses a cross order the three temperatures
  // cannot determine (v^3): that order is no candidate, the others are compared.
  TriadFitOptions own = classical_options(0);
  own.surface_options.erase("sf_cross_order");
  own.estimation = "sequential";
  own.sequential_scale = "surface";
  const TriadFit own_fit = fit_triad(d, own);
  EXPECT_TRUE(own_fit.summary.details["sf_cross_order_bic"]["3"].is_string());
  EXPECT_GE(std::stoi(own_fit.summary.details["surface_sf_cross_order"].get<std::string>()), 1);
  // The thesis's form when asked for.
  const TriadFit separable = fit_triad(d, classical_options(0));
  EXPECT_FALSE(separable.summary.details.contains("sf_cross_order_bic"));
  EXPECT_EQ(separable.summary.details["surface_sf_cross_order"], "0");
}

// A triad programme with few rate magnitudes per gyro, as an independent generator's (six axes at 20 and 45
// deg/s, the four diagonals both ways at 30 deg/s, a static hold after every turn; runs of `run` samples) and a
// scale factor falling with the square of each gyro's own rate (-5e-3 u^2, u = w / 100 deg/s: -1000 ppm at 45
// deg/s), biases linear in a temperature drifting 20 -> 30 C, white noise of `noise` rad/s per sample (seeded).
// Each gyro sees the magnitudes 17.3, 20, 21.2 and 45 deg/s (and ~0).
struct FewMagnitudeTriad {
  TriadModel truth;
  TriadData data;
  double noise_rms[3];  // the realised noise, rad/s
};
FewMagnitudeTriad few_magnitude_triad(int run, double noise, std::uint64_t seed) {
  FewMagnitudeTriad out;
  TriadModel& m = out.truth;
  m.misalignment << -6.5e-4, 8.6e-4, -2.9e-3, -6.7e-4, -9.7e-4, -1.8e-3, 4.4e-3, 2.8e-3, 3.3e-3;
  m.bias.reference_c = 25.0;
  m.bias.scale_c = 5.0;
  for (int a = 0; a < 3; ++a) m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::Vector2d(dph_to_radps(40.0 * (a - 1)), dph_to_radps(15.0));
  for (int a = 0; a < 3; ++a) {
    auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
    surface->rate_scale = dps_to_radps(100.0);
    surface->bias = Eigen::VectorXd::Zero(1);
    surface->sf_temperature = Eigen::VectorXd::Zero(1);
    surface->sf_rate = Eigen::Vector3d(0.0, 0.0, -5e-3);
    m.surfaces[static_cast<std::size_t>(a)] = surface;
  }
  std::vector<std::pair<Eigen::Vector3d, double>> turns;
  for (double rate : {20.0, 45.0})
    for (int a = 0; a < 3; ++a)
      for (double sign : {1.0, -1.0}) turns.emplace_back(sign * Eigen::Vector3d::Unit(a), rate);
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(1, 0, 1), Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(1, 1, 1)})
    for (double sign : {1.0, -1.0}) turns.emplace_back(sign * v.normalized(), 30.0);
  std::vector<Eigen::Vector3d> rates;
  for (const auto& [u, rate] : turns)
    for (double r : {rate, 0.0})
      for (int k = 0; k < run; ++k) rates.push_back(dps_to_radps(r) * u);
  TriadData& d = out.data;
  d = triad_at_outputs(rates);
  for (Eigen::Index k = 0; k < d.size(); ++k) d.temp_c.row(k).setConstant(20.0 + 10.0 * static_cast<double>(k) / static_cast<double>(d.size()));
  d.reference = d.gyro;
  for (int it = 0; it < 30; ++it) d.gyro = m.predict_outputs(d);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  for (int a = 0; a < 3; ++a) {
    double sum = 0.0;
    for (Eigen::Index k = 0; k < d.size(); ++k) {
      const double e = normal(rng);
      d.gyro(k, a) += e;
      sum += e * e;
    }
    out.noise_rms[a] = std::sqrt(sum / static_cast<double>(d.size()));
  }
  return out;
}

// The classical triad surfaces' rate order (surface.sf_rate_order=auto; the default bic_lr keeps BIC's) on a programme of
// four rate magnitudes per gyro. The thesis's order 6 leaves M_ii's column nearly in the span of the odd rate
// powers there: sigma(M_ii) grows tenfold and more. Before the surfaces' input left each sample out of its own
// average, those near-degenerate powers also fitted the input's share of the noise - residuals below the
// noise, BIC preferring order 6 and scale factors 3-5 % off (independent generator, 2026-11-25). Chosen here:
// the planted order 2, the scale factors within 4 sigma at sigma < 100 ppm, the off-diagonals at theirs.
TEST(TriadFit, ClassicalSurfacesChooseTheRateOrderTheProgrammeDetermines) {
  const double noise = dps_to_radps(0.04);  // 144 deg/h per sample
  const FewMagnitudeTriad t = few_magnitude_triad(400, noise, 3);
  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 1;
  o.surface_options = {{"sf_temperature_order", "0"}};
  const TriadFit f = fit_triad(t.data, o);
  ASSERT_TRUE(f.summary.details.contains("sf_rate_order_bic"));
  EXPECT_EQ(f.summary.details["sf_rate_order_bic"].size(), 7u);
  EXPECT_EQ(f.summary.details["surface_sf_rate_order"], "2");
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(f.uncertainty.misalignment_sigma(i, i), 100e-6) << i;
    EXPECT_NEAR(f.model.misalignment(i, i), t.truth.misalignment(i, i), 4.0 * f.uncertainty.misalignment_sigma(i, i)) << i;
    for (int j = 0; j < 3; ++j)
      if (j != i) {
        EXPECT_NEAR(f.model.misalignment(i, j), t.truth.misalignment(i, j), 4.0 * f.uncertainty.misalignment_sigma(i, j)) << i << j;
      }
  }
  // The thesis's order: the same data, M_ii ten times less determined; and no residual below the noise, as
  // an input carrying its own sample's noise gave (by about 1/61 of the variance per spare power).
  o.surface_options = {{"sf_temperature_order", "0"}, {"sf_rate_order", "6"}, {"sf_cross_order", "0"}};
  const TriadFit six = fit_triad(t.data, o);
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(six.uncertainty.misalignment_sigma(i, i), 10.0 * f.uncertainty.misalignment_sigma(i, i)) << i;
    EXPECT_NEAR(six.model.misalignment(i, i), t.truth.misalignment(i, i), 4.0 * six.uncertainty.misalignment_sigma(i, i)) << i;
  }
}

// The information criterion every triad fit writes (triad_fit.h): BIC = sum_i R ln(rss_i / R) + k ln(3 R),
// recomputed here from the fitted model's own residuals at the samples (rate rows: one per sample, weight 1) and
// the parameters the fit estimated, counted from the options: M (9) and b (3 x 2) without surfaces; plus the
// classical term's 7 columns per gyro jointly (v w | u w, u^2 w, u^3 w | v u w, v u^2 w, v u^3 w); sequentially
// the same 36 (the 6 off-diagonals estimated in the first stage, held in the second, counted once), and with the
// surface fitter's own form 15 + 3 x 10 (its bias 2, v w 1, u^0..u^3 w 4, cross 3).
TEST(TriadFit, EveryFitWritesItsInformationCriterionAsDefined) {
  const TriadData d = noisy_outputs_of_planted_cross_triad(11);
  struct Case {
    std::string surfaces, estimation, scale;
    int parameters;
  };
  for (const Case& c : {Case{"none", "joint", "triad", 15}, Case{"classical", "joint", "triad", 36}, Case{"classical", "sequential", "triad", 36},
                        Case{"classical", "sequential", "surface", 45}}) {
    TriadFitOptions o = classical_options(1);
    o.surfaces = c.surfaces;
    if (c.surfaces == "none") o.surface_options.clear();
    o.estimation = c.estimation;
    o.sequential_scale = c.scale;
    o.surface_input = "measured";  // the surfaces' fitting input is then the recorded output the recomputation uses
    const TriadFit f = fit_triad(d, o);
    const std::string label = c.surfaces + " " + c.estimation + " " + c.scale;
    const Eigen::MatrixX3d residual = f.model.predict_outputs(d) - d.gyro;
    const double rows = static_cast<double>(d.size());
    double bic = c.parameters * std::log(3.0 * rows);
    for (int a = 0; a < 3; ++a) bic += rows * std::log(residual.col(a).squaredNorm() / rows);
    const nlohmann::json ic = triad_fit_json(f, {})["summary"]["details"]["information_criterion"];
    EXPECT_EQ(ic["rows_per_gyro"].get<int>(), d.size()) << label;
    EXPECT_EQ(ic["parameters"].get<int>(), c.parameters) << label;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(ic["rss_radps2"][a].get<double>(), residual.col(a).squaredNorm(), 1e-9 * residual.col(a).squaredNorm()) << label;
    EXPECT_NEAR(ic["bic"].get<double>(), bic, 1e-9 * std::abs(bic)) << label;
    EXPECT_EQ(ic["bic"].get<double>(), f.criterion.bic) << label;
    const double aic = bic - c.parameters * std::log(3.0 * rows) + 2.0 * c.parameters;  // AIC = -2 ln L + 2 k
    EXPECT_NEAR(ic["aic"].get<double>(), aic, 1e-9 * std::abs(aic)) << label;
  }
}

// order_criterion=aic: the orders chosen by AIC (penalty 2 per parameter against BIC's ln(3R) > 2). For nested
// candidates the AIC minimiser is never a lower order than the BIC one (if BIC prefers order b to a lower a, the
// likelihood gain from a to b exceeds (k_b - k_a) ln(3R) > 2 (k_b - k_a), so AIC prefers b too), and on these
// four rate magnitudes, where orders above the planted 2 only trade with M_ii, every order above it adds 3
// parameters for a likelihood gain of a few units: AIC must still keep 2 or go higher, and it takes the lowest
// AIC it wrote.
TEST(TriadFit, AkaikesCriterionChoosesNoLowerOrderThanSchwarzs) {
  const FewMagnitudeTriad t = few_magnitude_triad(400, dps_to_radps(0.04), 3);
  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 1;
  o.surface_options = {{"sf_temperature_order", "0"}, {"sf_cross_order", "0"}};
  const TriadFit by_bic = fit_triad(t.data, o);
  o.order_criterion = "aic";
  const TriadFit by_aic = fit_triad(t.data, o);
  ASSERT_TRUE(by_aic.summary.details.contains("sf_rate_order_aic"));
  EXPECT_FALSE(by_aic.summary.details.contains("sf_rate_order_bic"));
  const int bic_order = std::stoi(by_bic.summary.details["surface_sf_rate_order"].get<std::string>());
  const int aic_order = std::stoi(by_aic.summary.details["surface_sf_rate_order"].get<std::string>());
  EXPECT_EQ(bic_order, 2);
  EXPECT_GE(aic_order, bic_order);
  double lowest = INFINITY;
  int argmin = -1;
  for (const auto& [order, value] : by_aic.summary.details["sf_rate_order_aic"].items()) {
    if (value.is_number() && value.get<double>() < lowest) lowest = value.get<double>(), argmin = std::stoi(order);
  }
  EXPECT_EQ(aic_order, argmin);
  EXPECT_EQ(by_aic.criterion.aic, lowest);
  o.order_criterion = "aicc";
  EXPECT_NE(o.validate().find("order_criterion"), std::string::npos);
}

using testing_support::hand_turn_bias;
using testing_support::hand_turn_misalignment;
using testing_support::hand_turn_session;

TEST(TriadFit, HandTurnsKnownByGravityRecoverThePlantedMatrix) {
  const Eigen::Matrix3d m = hand_turn_misalignment();
  const Eigen::Vector3d bias = hand_turn_bias();
  const TriadData d = hand_turn_session(m, bias, 11, 0.0, 0.0);
  TriadFitOptions o;
  o.bias_order = 0;
  o.reference = "gravity";
  const TriadFit f = fit_triad(d, o);
  EXPECT_LT((f.model.misalignment - m).cwiseAbs().maxCoeff(), 1e-9) << f.model.misalignment;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(f.model.bias.at(a, 25.0), bias(a), 1e-12) << a;
  for (const auto& row : f.uncertainty.misalignment_known)
    for (bool known : row) EXPECT_TRUE(known);
  EXPECT_NE(f.reference.find("13 hand turns"), std::string::npos) << f.reference;
  // Four turns (8 constraints) cannot determine nine entries: refused, not fitted.
  TriadData few = d;
  const auto last = static_cast<Eigen::Index>(5 * 100 + 4 * 150);
  few.t_s.resize(static_cast<std::size_t>(last));
  few.position_id.resize(static_cast<std::size_t>(last));
  few.gyro.conservativeResize(last, 3);
  few.accel.conservativeResize(last, 3);
  few.reference.conservativeResize(last, 3);
  few.temp_c.conservativeResize(last, 3);
  try {
    fit_triad(few, o);
    ADD_FAILURE() << "four turns were fitted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at least 5 turns"), std::string::npos) << e.what();
  }
}

// Holds checked for stillness (hold_stillness.h): a hand-turned session with white gyro noise (0.05 deg/s per
// sample), and hand motion planted in hold 5 - a 2 Hz wobble of 1 deg/s amplitude about x, std 1/sqrt(2) deg/s.
// The moving hold is named with its interval and deviation; no still hold is; a noise-only session names none.
TEST(TriadFit, HoldsThatAreNotStillAreNamedAndStillOnesAreNot) {
  const double noise = dps_to_radps(0.05);
  TriadData d = hand_turn_session(hand_turn_misalignment(), hand_turn_bias(), 5, noise, 1e-3);
  TriadFitOptions o;
  o.bias_order = 0;
  o.reference = "gravity";
  const TriadFit quiet = fit_triad(d, o);
  EXPECT_TRUE(quiet.hold_stillness.not_still().empty()) << quiet.hold_stillness.json().dump();
  EXPECT_EQ(quiet.hold_stillness.holds.size(), 14u);
  for (Eigen::Index k = 0; k < d.size(); ++k) {  // 100 samples of 0.01 s: 2 whole periods of the wobble
    if (d.position_id[static_cast<std::size_t>(k)] == 5) d.gyro(k, 0) += dps_to_radps(1.0) * std::sin(2.0 * units::kPi * 2.0 * d.t_s[static_cast<std::size_t>(k)]);
  }
  const TriadFit moved = fit_triad(d, o);
  const auto bad = moved.hold_stillness.not_still();
  ASSERT_EQ(bad.size(), 1u) << moved.hold_stillness.json().dump();
  EXPECT_EQ(bad[0].position_id, 5);
  EXPECT_EQ(bad[0].t_start_s, d.t_s[4 * 250]);  // holds of 100 samples, turns of 150 before it
  EXPECT_EQ(bad[0].t_end_s, d.t_s[4 * 250 + 99]);
  // The wobble's 1/sqrt(2) deg/s and the noise's 0.05 in quadrature, within the noise's scatter.
  EXPECT_NEAR(bad[0].gyro_std_dps[0], std::sqrt(0.5 + 0.05 * 0.05), 0.01);
  EXPECT_NEAR(bad[0].gyro_std_dps[1], 0.05, 0.01);
  EXPECT_GT(bad[0].ratio, 10.0);
  bool named = false;
  for (const auto& note : moved.notes) named = named || note.find("hold position_id 5 (") != std::string::npos;
  EXPECT_TRUE(named);
  const auto& details = moved.summary.details.at("hold_stillness");
  EXPECT_EQ(details.at("not_still").size(), 1u);
  EXPECT_EQ(details.at("not_still")[0].at("position_id"), 5);
  EXPECT_EQ(details.at("holds_checked"), 14);
}

// The intervals of reference=gravity (gravity_turns.h: each hold's direction uncertain by its accelerometer
// noise, shared by the turns before and after it; the gyro noise over a turn; residuals in each turn's tangent
// plane, 2 per turn). 40 sessions with noise on both, the accelerometer otherwise exact: the errors of the nine
// entries spread as their sigmas say (measured: 0.86, 77 % inside 1 sigma; the tangent plane without the
// weights 0.92). Three residuals per turn, one of them ~0, made each sigma ~1/sqrt(2/3) = 1.22x too small.
TEST(TriadFit, HandTurnsKnownByGravityReportSigmasTheErrorsFollow) {
  const Eigen::Matrix3d m = hand_turn_misalignment();
  const Eigen::Vector3d bias = hand_turn_bias();
  TriadFitOptions o;
  o.bias_order = 0;
  o.reference = "gravity";
  double sum2 = 0.0;
  int inside = 0, count = 0;
  for (std::uint64_t seed = 100; seed < 140; ++seed) {
    const TriadFit f = fit_triad(hand_turn_session(m, bias, seed, 2e-3, 0.05), o);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double z = (f.model.misalignment(i, j) - m(i, j)) / f.uncertainty.misalignment_sigma(i, j);
        sum2 += z * z, inside += std::abs(z) <= 1.0, ++count;
      }
  }
  const double z_sd = std::sqrt(sum2 / count);
  EXPECT_GT(z_sd, 0.75);
  EXPECT_LT(z_sd, 1.1);
  EXPECT_GT(static_cast<double>(inside) / count, 0.58);  // 0.68 nominal; 360 values
}

TEST(TriadModel, FileRoundTripAndCompensationInvertTheModelExactly) {
  TriadModel m;
  m.misalignment << 2e-4, -1e-3, 3e-3, 8e-4, -5e-4, 1.4e-3, 4e-4, -1e-3, 1e-4;
  m.bias.reference_c = 20.0;
  m.bias.scale_c = 30.0;
  for (int a = 0; a < 3; ++a) m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::Vector3d(dph_to_radps(-15 + a), dph_to_radps(2.0), dph_to_radps(-0.5));
  m.g_sensitivity = Eigen::Matrix3d::Constant(dph_to_radps(0.1));
  auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
  surface->bias = Eigen::VectorXd::Zero(1);
  surface->sf_temperature = Eigen::Vector2d(0.0, 1e-5);
  surface->sf_rate = Eigen::Vector3d(0.0, 0.0, -2e-4);
  surface->rate_scale = 1.0;
  m.surfaces[1] = surface;
  TriadData d;
  const int n = 50;
  d.gyro.resize(n, 3);
  d.temp_c.resize(n, 3);
  d.accel.resize(n, 3);
  for (int k = 0; k < n; ++k) {
    d.t_s.push_back(k);
    d.gyro.row(k) << std::sin(0.3 * k), 0.7 * std::cos(0.2 * k), -0.1 * k / n;
    d.temp_c.row(k).setConstant(-10.0 + k);
    d.accel.row(k) << 0.1 * k, -9.8, 1.0;
  }
  // Compensation then the forward model returns the outputs (the surfaces take the measured rate).
  d.reference = m.compensate(d);
  EXPECT_LT((m.predict_outputs(d) - d.gyro).cwiseAbs().maxCoeff(), 1e-15);
  const TriadModel back = triad_model_from_json(nlohmann::json::parse(triad_model_json(m).dump()), "<test>");
  EXPECT_EQ(back.compensate(d), m.compensate(d));
  EXPECT_FALSE(back.surfaces[0]);
  ASSERT_TRUE(back.surfaces[1]);
}

// A triad whose rate law no order the auto search offers (0..6) holds: each scale factor is 1000 ppm u^8,
// u = w / 150 deg/s, seen at -150..150 deg/s by 10 along the axes and five diagonals, 20 samples each, under
// white noise of `noise_dph` (the probe: every 1 deg/s, one noise-free sample). Order 4 leaves the law's misfit
// (1000 ppm / 2^5 at most, Chebyshev) and order 6 a quarter of it; at 150 deg/h per sample the likelihood gain
// from 4 to 6 is a few tens - under BIC's 6 ln(3R) = 58, above a chi^2(6) test's 16.8.
TriadData eighth_power_triad(double noise_dph, bool noisy, std::uint64_t seed) {
  TriadModel m = planted_rbf_triad([](int) { return Eigen::Vector2d(0.0, 0.0); });
  for (int a = 0; a < 3; ++a) {
    auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
    surface->rate_scale = dps_to_radps(150.0);
    surface->bias = Eigen::VectorXd::Zero(1);
    surface->sf_temperature = Eigen::VectorXd::Zero(1);
    surface->sf_rate = Eigen::VectorXd::Zero(9);
    surface->sf_rate(8) = 1e-3;
    m.surfaces[static_cast<std::size_t>(a)] = surface;
  }
  std::vector<double> rates;
  for (int r = -150; r <= 150; r += noisy ? 10 : 1) rates.push_back(r);
  TriadData d = turns_triad(m, rates, {25.0}, noisy ? 20 : 1);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, dph_to_radps(noise_dph));
  if (noisy)
    for (Eigen::Index k = 0; k < d.gyro.size(); ++k) d.gyro.data()[k] += normal(rng);
  return d;
}

// order_criterion=bic_lr (the default; triad_fit.h): BIC's order b, raised to the lowest order o >= b whose
// likelihood ratio against the top order, Lambda_o = (BIC_o - BIC_6) + 3 (6 - o) ln(3R) (one rate power per gyro
// per order), is at most chi^2_{3 (6 - o)}(0.99). Where the family holds the sensor (the planted order 2 of the
// four-magnitude triad) it keeps BIC's order, its statistic under the tabulated chi^2_12(0.99) = 26.217; where
// no order holds it (the u^8 law), it takes the order BIC stops short of, and that compensates the rates
// between the training's better on average over seeds (on one seed the order's variance may outweigh its bias).
TEST(TriadFit, TheLikelihoodRatioTestRaisesBicsOrderOnlyWhereTheDataShowItsLackOfFit) {
  auto statistic = [](const TriadFit& f, int order) {
    const nlohmann::json& bic = f.summary.details["sf_rate_order_bic"];
    return bic[std::to_string(order)].get<double>() - bic["6"].get<double>() + 3.0 * (6 - order) * std::log(3.0 * f.criterion.rows_per_gyro);
  };
  TriadFitOptions o;
  o.surfaces = "classical";
  o.bias_order = 1;
  o.surface_options = {{"sf_temperature_order", "0"}, {"sf_cross_order", "0"}};
  const FewMagnitudeTriad holds = few_magnitude_triad(400, dps_to_radps(0.04), 3);
  const TriadFit kept = fit_triad(holds.data, o);
  EXPECT_EQ(kept.summary.details["surface_sf_rate_order"], "2");
  const nlohmann::json& test2 = kept.summary.details["sf_rate_order_lr"]["2"];
  EXPECT_EQ(test2["dof"].get<int>(), 12);
  EXPECT_NEAR(test2["critical"].get<double>(), 26.217, 1e-3);
  EXPECT_NEAR(test2["statistic"].get<double>(), statistic(kept, 2), 1e-6 * std::abs(statistic(kept, 2)) + 1e-6);
  EXPECT_LT(test2["statistic"].get<double>(), 26.217);

  o.bias_order = 0;
  o.surface_input = "measured";  // turns at constant rate: no still rows to smooth over
  const TriadData probe = eighth_power_triad(0.0, false, 0);
  auto rms_dph = [&](const TriadFit& f) { return radps_to_dph(std::sqrt((f.model.compensate(probe) - probe.reference).squaredNorm() / static_cast<double>(probe.gyro.size()))); };
  double bic_sum = 0.0, test_sum = 0.0;
  int raised = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const TriadData training = eighth_power_triad(150.0, true, seed);
    o.order_criterion = "bic";
    const TriadFit by_bic = fit_triad(training, o);
    o.order_criterion = "bic_lr";
    const TriadFit by_test = fit_triad(training, o);
    const int b = std::stoi(by_bic.summary.details["surface_sf_rate_order"].get<std::string>());
    EXPECT_EQ(by_test.summary.details["surface_sf_rate_order"], "6") << seed;
    for (int order = b; order < 6; ++order) {
      const nlohmann::json& t = by_test.summary.details["sf_rate_order_lr"][std::to_string(order)];
      EXPECT_NEAR(t["statistic"].get<double>(), statistic(by_test, order), 1e-6 * std::abs(statistic(by_test, order))) << seed << " " << order;
      EXPECT_GT(t["statistic"].get<double>(), t["critical"].get<double>()) << seed << " " << order;
    }
    raised += b < 6;
    bic_sum += rms_dph(by_bic);
    test_sum += rms_dph(by_test);
  }
  // Measured: BIC order 6 on seed 1 and 4 on seeds 2-4; the probe's rms 6.7 / 9.3 / 8.9 / 10.2 deg/h by BIC,
  // 6.7 / 7.6 / 6.1 / 7.6 with the test.
  EXPECT_GE(raised, 2);
  EXPECT_LT(test_sum, 0.85 * bic_sum);
  o.order_test_level = 0.5;
  EXPECT_EQ(o.validate(), "");
  o.order_test_level = 0.7;
  EXPECT_NE(o.validate().find("order_test_level"), std::string::npos);
}

}  // namespace
}  // namespace gyrosid
