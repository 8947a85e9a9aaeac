// A prior over sensors updated by a recording (design/sensor_posterior.h): the likelihood against a direct
// evaluation where the noise is white, the member a recording came from preferred over its neighbours, the
// tempering's effective-member floor, and a design that continues recorded segments.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "design/design.h"
#include "design/sensor_posterior.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"

namespace gyrosid::design {
namespace {

TableProfile scan(double from_c, double to_c, double minutes) {
  TableProfile p;
  p.name = "scan";
  p.kind = "programme";
  p.latitude_rad = units::deg_to_rad(DesignSpaceOptions{}.latitude_deg);  // the design's
  ProfileSegment s;
  s.duration_s = minutes * 60.0;
  s.chamber_start_c = from_c, s.chamber_end_c = to_c;
  s.rate = RateProfile::triangle(units::dps_to_radps(-100), units::dps_to_radps(100), minutes, 0.0);
  p.segments.push_back(s);
  return p;
}

std::vector<double> times(double seconds, double rate_hz) {
  std::vector<double> t;
  for (std::size_t k = 0; static_cast<double>(k) < seconds * rate_hz; ++k) t.push_back(static_cast<double>(k) / rate_hz);
  return t;
}

GyroSensor reference() { return std::get<GyroSensor>(load_sensor_file("builtin:sensors/open_loop_fog.yaml")); }

GyroSensor white_only(GyroSensor g, double arw_rad_rt_s) {
  g.noise = NoiseOptions{};
  g.noise.arw_rad_rt_s = arw_rad_rt_s;
  g.quantization_rad = 0.0;
  return g;
}

// The member's noise-free output on the programme (the simulator's, with the noise stripped).
std::vector<double> exact_output_dps(const GyroSensor& g, const TableProfile& p, const std::vector<double>& t) {
  const GyroSensor exact = std::get<GyroSensor>(without_noise(g));
  const GyroOutput out = simulate_single(exact, excite(p, t, g.thermal.lag_options()), 0);
  std::vector<double> dps;
  for (double w : out.rate_radps) dps.push_back(units::radps_to_dps(w));
  return dps;
}

// White noise of variance v per sample and a free constant: log L = -1/2 [n log v + sum (r - rbar)^2 / v + log(n / v)].
TEST(SensorPosterior, TheLikelihoodUnderWhiteNoiseIsTheDirectGaussianOne) {
  const double arw = 2e-5, rate_hz = 2.0;
  const GyroSensor g = white_only(reference(), arw);
  const TableProfile p = scan(20, 40, 4);
  const std::vector<double> t = times(240, rate_hz);
  std::vector<double> y = exact_output_dps(g, p, t);
  RandomStream rng(3, "test/posterior");
  std::vector<double> r;
  for (double& x : y) {
    const double e = 0.05 + units::radps_to_dps(arw * std::sqrt(rate_hz)) * rng.normal();  // a bias and white noise
    x += e, r.push_back(units::dps_to_radps(e));
  }
  const double n = static_cast<double>(r.size()), v = arw * arw * rate_hz;
  const double mean = std::accumulate(r.begin(), r.end(), 0.0) / n;
  double ss = 0.0;
  for (double e : r) ss += (e - mean) * (e - mean);
  const double direct = -0.5 * (n * std::log(v) + ss / v + std::log(n / v));
  EXPECT_NEAR(recording_log_likelihood(g, p, t, y), direct, 1e-7 * std::abs(direct));
}

// A recording of one member (coloured noise, thermal lag, surface) is likelier under it than under the same
// sensor with a scale-factor asymmetry of 200 ppm (36 deg/h at 100 deg/s) or its white noise doubled; the untempered
// posterior picks it.
TEST(SensorPosterior, TheMemberThatRecordedIsPreferred) {
  const GyroSensor truth = reference();
  GyroSensor surface = truth, loud = truth;
  surface.errors.scale_factor_asymmetry += 200e-6;
  loud.noise.arw_rad_rt_s *= 2.0;
  const TableProfile p = scan(-20, 40, 12);
  TrajectorySpec spec;
  spec.profile = p;
  spec.sampling.rate_hz = 3.0;
  const Simulation sim = simulate(truth, spec, 5);
  const auto& t = sim.recording.column("t_s");
  const auto& y = sim.recording.column("gyro_dps");
  const std::vector<double> log_l{recording_log_likelihood(truth, p, t, y), recording_log_likelihood(surface, p, t, y),
                                  recording_log_likelihood(loud, p, t, y)};
  EXPECT_GT(log_l[0] - log_l[1], 10.0);
  EXPECT_GT(log_l[0] - log_l[2], 10.0);
  const SensorPosterior post = tempered_posterior({1, 1, 1}, log_l, 1.0);
  EXPECT_EQ(post.learning_rate, 1.0);
  EXPECT_GT(post.weights[0], 0.999);
}

TEST(SensorPosterior, TemperingKeepsTheEffectiveMembersAtTheFloor) {
  const std::vector<double> prior{1, 1, 1, 1}, log_l{0, -10, -20, -30};
  // Untempered: one member. A floor of 2 (half the prior's 4) tempers it to exactly 2 effective members.
  EXPECT_NEAR(tempered_posterior(prior, log_l, 1.0).effective_members, 1.0, 1e-4);
  const SensorPosterior p = tempered_posterior(prior, log_l, 2.0);
  EXPECT_GT(p.learning_rate, 0.0);
  EXPECT_LT(p.learning_rate, 1.0);
  EXPECT_NEAR(p.effective_members, 2.0, 1e-9);
  // The weights are the prior's times L^eta, normalised.
  double z = 0.0;
  for (double l : log_l) z += std::exp(p.learning_rate * l);
  for (std::size_t m = 0; m < 4; ++m) EXPECT_NEAR(p.weights[m], std::exp(p.learning_rate * log_l[m]) / z, 1e-12);
  // A floor above half the prior's own effective members is lowered to it: two members, the likelier wins.
  EXPECT_EQ(tempered_posterior({1, 1}, {0, -50}, 2.0).learning_rate, 1.0);
  // Near-equal likelihoods need no tempering; bad inputs are named.
  EXPECT_EQ(tempered_posterior(prior, {0, -0.1, -0.2, -0.3}, 2.0).learning_rate, 1.0);
  EXPECT_THROW(tempered_posterior({1, 0}, {0, 0}, 2.0), Error);
  EXPECT_THROW(tempered_posterior({1, 1}, {0, NAN}, 2.0), Error);
}

// A design after recorded segments starts where the chamber is, fills the new budget and is predicted on
// recorded + new.
TEST(SensorPosterior, ADesignContinuesTheRecordedSegments) {
  const SensorSpec sensor = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  DesignSettings settings;
  settings.envelope.flights = {"short"};
  settings.space.segments = 2;
  auto envelope = std::make_shared<const Envelope>(load_envelope(settings.envelope, as_triad(sensor)));
  const DesignSpace space = design_space(*envelope, settings.space);
  DesignContext context(sensor, envelope, ModelFamily::classical, settings.model, Criterion::cof, model_domain(space));
  DesignRequest request;
  request.space = settings.space;
  request.space.budget_min = 6.0;
  request.solver_options = {{"global_evaluations", "30"}, {"local_evaluations", "20"}};
  request.recorded = scan(10, 30, 4);
  const DesignResult r = design_trajectory(context, request);
  EXPECT_EQ(r.trajectory.profile.segments.front().chamber_start_c, 30.0);
  EXPECT_NEAR(r.trajectory.profile.duration_min(), 6.0, 1e-9);
  EXPECT_NEAR(r.predicted.duration_min, 10.0, 1e-9);
  EXPECT_EQ(concatenate(request.recorded, r.trajectory.profile).check_limits(), "");
  request.solver = "ipopt";
  EXPECT_THROW(design_trajectory(context, request), Error);
  EXPECT_THROW(concatenate(scan(10, 30, 4), scan(20, 30, 4)), Error);  // the chamber cannot jump
}

}  // namespace
}  // namespace gyrosid::design
