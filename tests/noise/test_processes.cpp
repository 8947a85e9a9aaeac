// Each noise process simulated alone, its coefficient recovered from the Allan curve (IEEE Std 952
// Annex C), plus the statistics of the exact discretisation.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/units.h"
#include "noise/allan.h"
#include "noise/identify.h"
#include "sensor/gyro_sensor.h"
#include "noise/processes.h"

namespace gyrosid {
namespace {

using namespace units;

std::vector<double> simulate_noise(const NoiseOptions& o, double dt, std::size_t n, std::uint64_t seed) {
  NoiseGenerator g(o, seed, "test");
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = radps_to_dph(g.next(k * dt, dt));  // deg/h
  return out;
}

TEST(Noise, AngleRandomWalkRecoveredWithin5PercentFrom10hAt100Hz) {
  NoiseOptions o;
  o.arw_rad_rt_s = deg_rt_h_to_rad_rt_s(0.15);
  const double dt = 0.01;
  const auto y = simulate_noise(o, dt, 3600000, 1);
  const NoiseIdentification fit = identify_noise(y, dt);
  const double n_deg_rt_h = fit.model.white / 60.0;  // (deg/h) sqrt(s) -> deg/sqrt(h)
  EXPECT_NEAR(n_deg_rt_h, 0.15, 0.05 * 0.15);
  EXPECT_EQ(fit.structure.name(), "N");  // nothing invented
}

TEST(Noise, WhiteSampleSigmaIsNOverRootDt) {
  NoiseOptions o;
  o.arw_rad_rt_s = dph_to_radps(10.0);  // 10 deg/h at 1 Hz
  const double dt = 0.25;
  const auto y = simulate_noise(o, dt, 400000, 2);
  double s2 = 0;
  for (double v : y) s2 += v * v;
  EXPECT_NEAR(std::sqrt(s2 / y.size()), 10.0 / std::sqrt(dt), 0.01 * 20.0);
}

TEST(Noise, GaussMarkovIntervalMeansHaveTheExactMoments) {
  // Samples are interval means of the process. With r = h/tau, the stationary moments of the integral over
  // one interval are var = 2 sigma^2 tau^2 (r - 1 + e^-r) and lag-1 covariance sigma^2 tau^2 (1 - e^-r)^2.
  // With h = tau an Euler scheme (thesis eq 3.55) would be far off; the exact generation is not.
  NoiseOptions o;
  const double sigma = 5.0, tau = 2.0, h = 2.0;
  o.gauss_markov.push_back({dph_to_radps(sigma), tau});
  const auto y = simulate_noise(o, h, 400000, 3);
  double s2 = 0, s11 = 0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    s2 += y[k] * y[k];
    if (k) s11 += y[k] * y[k - 1];
  }
  const double r = h / tau;
  const double var = 2 * sigma * sigma * tau * tau * (r - 1 + std::exp(-r)) / (h * h);
  const double cov1 = sigma * sigma * tau * tau * std::pow(1 - std::exp(-r), 2) / (h * h);
  EXPECT_NEAR(s2 / y.size(), var, 0.02 * var);
  EXPECT_NEAR(s11 / s2, cov1 / var, 0.01);
}

TEST(Noise, GaussMarkovRecoveredFromTheAllanCurve) {
  NoiseOptions o;
  o.gauss_markov.push_back({dph_to_radps(5.0), 100.0});
  const double dt = 0.1;
  const auto y = simulate_noise(o, dt, 360000, 4);  // 10 h
  const GaussMarkovFit fit = fit_gauss_markov(overlapping_allan_deviation(y, dt), false);
  EXPECT_NEAR(fit.sigma, 5.0, 0.10 * 5.0);
  EXPECT_NEAR(fit.tau_s, 100.0, 0.20 * 100.0);
}

TEST(Noise, BiasInstabilityRecoveredFromItsFlickerFloor) {
  NoiseOptions o;
  o.bias_instability_radps = dph_to_radps(0.5);
  o.bias_instability_tau_min_s = 0.01;  // the 1/f band covers every averaging time of the 20-h record
  o.bias_instability_tau_max_s = 1e6;
  const double dt = 0.1;
  const auto y = simulate_noise(o, dt, 720000, 5);  // 20 h
  NoiseIdOptions flicker;
  flicker.terms = "B";
  const NoiseIdentification fit = identify_noise(y, dt, flicker);
  EXPECT_NEAR(fit.model.flicker, 0.5, 0.05 * 0.5);
}

TEST(Noise, BiasInstabilityComponentsHaveAFlatAllanFloorInTheBand) {
  // The analytic Allan deviation of the Gauss-Markov sum is within 15 % of 0.664 B across the band interior.
  const auto parts = bias_instability_components(1.0, 1.0, 1e4, 3);
  for (double t = 5.0; t < 2000.0; t *= 1.5) {
    double var = 0;
    for (const auto& gm : parts) var += gauss_markov_allan_variance(gm.sigma_radps, gm.tau_s, t);
    EXPECT_NEAR(std::sqrt(var), std::sqrt(2 * std::log(2.0) / std::numbers::pi), 0.15 * 0.664) << "tau " << t;
  }
}

TEST(Noise, RateRandomWalkRecovered) {
  NoiseOptions o;
  o.rrw_rad_s_rt_s = dph_rt_h_to_rad_s_rt_s(2.0);
  const double dt = 0.1;
  const auto y = simulate_noise(o, dt, 720000, 6);  // 20 h
  const NoiseIdentification fit = identify_noise(y, dt);
  EXPECT_EQ(fit.structure.name(), "K");
  EXPECT_NEAR(fit.model.random_walk * 60.0, 2.0, 0.1 * 2.0);  // (deg/h)/sqrt(s) -> (deg/h)/sqrt(h)
  EXPECT_LE(fit.parameters[0].low * 60.0, 2.0);
  EXPECT_GE(fit.parameters[0].high * 60.0, 2.0);
}

TEST(Noise, RateRampRecovered) {
  NoiseOptions o;
  o.rate_ramp_radps2 = dph_per_h_to_radps2(10.0);
  const double dt = 1.0;
  const auto y = simulate_noise(o, dt, 36000, 7);
  const NoiseIdentification fit = identify_noise(y, dt);
  EXPECT_EQ(fit.structure.name(), "R");
  EXPECT_NEAR(fit.model.ramp * 3600.0, 10.0, 0.01 * 10.0);
}

TEST(Noise, QuantizationRecoveredAsPulseWeightOverRoot12) {
  // Angle quantization with pulse weight q leaves an angle error uniform on [0, q) - white phase noise of
  // variance q^2/12 when the angle moves by many pulses per sample: sigma^2 = 3 Q^2/tau^2, Q = q/sqrt(12).
  GyroSensor s;
  s.quantization_rad = 1.0 * kArcsecToRad;
  Excitation ex;
  const double dt = 0.01;
  std::vector<double> truth;
  for (int k = 0; k < 360000; ++k) {
    const double t = k * dt;
    ex.t_s.push_back(t);
    ex.omega_ib_b.push_back(Eigen::Vector3d(0, 0, dps_to_radps(20.0 + 50.0 * std::sin(0.37 * t))));
    ex.f_b.push_back(Eigen::Vector3d::Zero());
    ex.coil_temp_c.push_back(25);
    ex.coil_temp_rate_c_per_s.push_back(0);
  }
  const GyroOutput out = simulate_single(s, ex, 8);
  std::vector<double> y(out.rate_radps.size());
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = radps_to_dph(out.rate_radps[k] - ex.omega_ib_b[k].z());
  NoiseIdOptions quantization;
  quantization.terms = "Q";
  const NoiseIdentification fit = identify_noise(y, dt, quantization);
  EXPECT_NEAR(fit.model.quantization, 1.0 / std::sqrt(12.0), 0.05 / std::sqrt(12.0));  // (deg/h) s = arcsec
}

TEST(Noise, SameSeedIsBitIdenticalAndOptionsAreValidated) {
  NoiseOptions o;
  o.arw_rad_rt_s = 1e-4;
  o.bias_instability_radps = 1e-5;
  o.gauss_markov.push_back({1e-5, 10.0});
  EXPECT_EQ(simulate_noise(o, 0.1, 1000, 9), simulate_noise(o, 0.1, 1000, 9));
  EXPECT_NE(simulate_noise(o, 0.1, 1000, 9), simulate_noise(o, 0.1, 1000, 10));
  NoiseOptions bad;
  bad.gauss_markov.push_back({1e-5, 0.0});
  EXPECT_NE(bad.validate(), "");
  bad = NoiseOptions{};
  bad.bias_instability_tau_max_s = 0.05;  // below tau_min
  EXPECT_NE(bad.validate(), "");
}

}  // namespace
}  // namespace gyrosid
