// Every term of the unified model (thesis eq 3.48): the forward model against its closed form, and the
// inverse (eq 3.44) recovering the true rate to 1e-9 deg/s without noise. Quantization and saturation are
// not invertible; their tests bound what they lose.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/random.h"
#include "core/units.h"
#include "sensor/gyro_error_model.h"
#include "sensor/gyro_sensor.h"
#include "sensor/sensor_config.h"

namespace gyrosid {
namespace {

using namespace units;

struct Term {
  const char* name;
  std::function<void(GyroErrorModel&)> set;
  // Closed form of forward(omega) - omega.
  std::function<double(double omega, const GyroEnvironment&)> expected_error;
};

SplineSurface reference_surface() {
  const auto spec = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  return *std::get<GyroSensor>(spec).errors.scale_factor_surface;
}

std::vector<Term> terms() {
  const Eigen::Vector3d kg(dph_to_radps(2.0), dph_to_radps(-1.0), dph_to_radps(3.0));
  Eigen::Matrix3d kgg;
  kgg << 0.02, 0.01, 0.0, 0.01, -0.03, 0.005, 0.0, 0.005, 0.04;
  kgg *= dph_to_radps(1.0);
  const SplineSurface surface = reference_surface();
  return {
      {"constant bias", [](GyroErrorModel& m) { m.bias_radps = dph_to_radps(-15); },
       [](double, const GyroEnvironment&) { return dph_to_radps(-15); }},
      {"bias vs temperature (cubic)",
       [](GyroErrorModel& m) { m.bias_temperature_radps = {{dph_to_radps(1), dph_to_radps(0.12), dph_to_radps(-0.0025), dph_to_radps(4e-5)}, 25.0}; },
       [](double, const GyroEnvironment& e) {
         const double u = e.temp_c - 25;
         return dph_to_radps(1 + 0.12 * u - 0.0025 * u * u + 4e-5 * u * u * u);
       }},
      {"scale factor vs temperature",
       [](GyroErrorModel& m) { m.scale_factor_temperature = {{100e-6, 3e-6, -0.05e-6}, 20.0}; },
       [](double w, const GyroEnvironment& e) {
         const double u = e.temp_c - 20;
         return (100e-6 + 3e-6 * u - 0.05e-6 * u * u) * w;
       }},
      {"scale factor vs rate (6th order)",
       [](GyroErrorModel& m) { m.scale_factor_rate = {{0, 2e-4, -8e-4, 0, 3e-4, 0, -1e-5}, 0.0}; },
       [](double w, const GyroEnvironment&) {
         return (2e-4 * w - 8e-4 * w * w + 3e-4 * std::pow(w, 4) - 1e-5 * std::pow(w, 6)) * w;
       }},
      {"scale-factor surface (reference grid)", [surface](GyroErrorModel& m) { m.scale_factor_surface = surface; },
       [surface](double w, const GyroEnvironment& e) { return surface(e.temp_c, w).value * w; }},
      {"scale-factor asymmetry", [](GyroErrorModel& m) { m.scale_factor_asymmetry = 400e-6; },
       [](double w, const GyroEnvironment&) { return (w > 0 ? 200e-6 : w < 0 ? -200e-6 : 0.0) * w; }},
      {"Shupe (temperature rate)", [](GyroErrorModel& m) { m.shupe_rad_per_c = dph_to_radps(3.0) * 60.0; },
       [](double, const GyroEnvironment& e) { return dph_to_radps(3.0) * 60.0 * e.temp_rate_c_per_s; }},
      {"g-sensitivity", [kg](GyroErrorModel& m) { m.g_sensitivity = kg; },
       [kg](double, const GyroEnvironment& e) { return kg.dot(e.f_s); }},
      {"g2-sensitivity", [kgg](GyroErrorModel& m) { m.g2_sensitivity = kgg; },
       [kgg](double, const GyroEnvironment& e) { return e.f_s.dot(kgg * e.f_s); }},
  };
}

GyroEnvironment random_environment(RandomStream& r) {
  GyroEnvironment e;
  e.temp_c = -20 + 80 * r.uniform();
  e.temp_rate_c_per_s = c_per_min_to_c_per_s(-5 + 10 * r.uniform());
  e.f_s = Eigen::Vector3d(r.normal(), r.normal(), r.normal()) * 10.0;
  return e;
}

TEST(GyroErrorModel, EachTermForwardMatchesItsClosedFormAndInverseRecoversTheRate) {
  RandomStream r(11, "env");
  for (const Term& term : terms()) {
    GyroErrorModel m;
    term.set(m);
    ASSERT_EQ(m.validate(dps_to_radps(100)), "") << term.name;
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {
      const double w = dps_to_radps(-100 + 200 * r.uniform());
      const GyroEnvironment e = random_environment(r);
      const double meas = m.forward(w, e);
      EXPECT_NEAR(meas - w, term.expected_error(w, e), 1e-15 + 1e-12 * std::abs(meas - w)) << term.name;
      worst = std::max(worst, std::abs(radps_to_dps(m.inverse(meas, e) - w)));
    }
    EXPECT_LT(worst, 1e-9) << term.name << ": forward then inverse misses by " << worst << " deg/s";
  }
}

TEST(GyroErrorModel, AllTermsTogetherInvertAcrossZeroRate) {
  GyroErrorModel m;
  for (const Term& term : terms()) term.set(m);
  RandomStream r(12, "env");
  for (double dps : {-100.0, -1e-3, -1e-9, 0.0, 1e-9, 1e-3, 0.4, 100.0}) {
    const GyroEnvironment e = random_environment(r);
    const double w = dps_to_radps(dps);
    EXPECT_LT(std::abs(radps_to_dps(m.inverse(m.forward(w, e), e) - w)), 1e-9) << dps << " deg/s";
  }
}

TEST(GyroErrorModel, ValidationRefusesANonInvertibleScaleFactor) {
  GyroErrorModel m;
  m.scale_factor_rate = {{0, -2.0}, 0.0};  // dSF = -2 omega: forward has a maximum, no inverse
  EXPECT_NE(m.validate(1.0), "");
}

Excitation constant_excitation(std::size_t n, double dt, double rate_radps) {
  Excitation ex;
  for (std::size_t k = 0; k < n; ++k) {
    ex.t_s.push_back(k * dt);
    ex.omega_ib_b.push_back(Eigen::Vector3d(0, 0, rate_radps));
    ex.f_b.push_back(Eigen::Vector3d(0, 0, 9.8));
    ex.chamber_temp_c.push_back(25);
    ex.probe_temp_c.push_back(25);
    ex.coil_temp_c.push_back(25);
    ex.coil_temp_rate_c_per_s.push_back(0);
  }
  return ex;
}

TEST(GyroSensor, QuantizationLosesLessThanOnePulseOfAngle) {
  GyroSensor s;
  s.quantization_rad = 2.0 * kArcsecToRad;
  s.noise.arw_rad_rt_s = deg_rt_h_to_rad_rt_s(0.05);
  const double dt = 0.01, rate = dps_to_radps(0.0123);
  const Excitation ex = constant_excitation(20000, dt, rate);
  const GyroOutput out = simulate_single(s, ex, 5);
  GyroSensor unquantized = s;
  unquantized.quantization_rad = 0;
  const GyroOutput ref = simulate_single(unquantized, ex, 5);  // same noise draws
  double angle = 0, ref_angle = 0, worst = 0;
  for (std::size_t k = 0; k < ex.size(); ++k) {
    angle += out.rate_radps[k] * dt;
    ref_angle += ref.rate_radps[k] * dt;
    worst = std::max(worst, std::abs(angle - ref_angle));
    // Each output is a whole number of pulses per sample.
    const double pulses = out.rate_radps[k] * dt / s.quantization_rad;
    ASSERT_NEAR(pulses, std::round(pulses), 1e-6);
  }
  EXPECT_LE(worst, s.quantization_rad * (1 + 1e-9));
}

TEST(GyroSensor, SaturationClipsAtTheRangeAndCounts) {
  GyroSensor s;
  s.range_radps = dps_to_radps(100);
  const GyroOutput out = simulate_single(s, constant_excitation(10, 0.1, dps_to_radps(150)), 1);
  EXPECT_EQ(out.saturated_samples, 10u);
  EXPECT_DOUBLE_EQ(out.rate_radps[3], dps_to_radps(100));
  const GyroOutput inside = simulate_single(s, constant_excitation(10, 0.1, dps_to_radps(-99)), 1);
  EXPECT_EQ(inside.saturated_samples, 0u);
  EXPECT_DOUBLE_EQ(inside.rate_radps[0], dps_to_radps(-99));
}

TEST(GyroSensor, ReferenceSensorConfigLoadsWithTheThesisFigures) {
  const auto spec = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  const GyroSensor& g = std::get<GyroSensor>(spec);
  EXPECT_NEAR(radps_to_dph(g.errors.bias_radps), -15.0, 1e-12);
  EXPECT_NEAR(g.noise.arw_rad_rt_s, dph_to_radps(10.0), 1e-15);  // sigma 10 deg/h at 1 Hz
  EXPECT_DOUBLE_EQ(g.thermal.tau_s, 300.0);
  ASSERT_TRUE(g.errors.scale_factor_surface.has_value());
  // The thesis grid, extended by synthetic rows at the ends of its calibration scans (-60 and 80 C).
  EXPECT_EQ(g.errors.scale_factor_surface->x(), (std::vector<double>{-60, -20, 0, 20, 25, 40, 60, 80}));
  EXPECT_EQ(g.errors.scale_factor_surface->y().size(), 12u);
  // Peak rate error of the surface about 0.1 deg/s.
  double peak = 0;
  for (double t = -20; t <= 60; t += 1)
    for (double w = -100; w <= 100; w += 1) {
      GyroErrorModel sf_only;
      sf_only.scale_factor_surface = g.errors.scale_factor_surface;
      peak = std::max(peak, std::abs(radps_to_dps(sf_only.forward(dps_to_radps(w), {t, 0}) - dps_to_radps(w))));
    }
  EXPECT_GT(peak, 0.08);
  EXPECT_LT(peak, 0.12);
}

}  // namespace
}  // namespace gyrosid
