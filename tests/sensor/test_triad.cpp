// The triad simulator: body rates -> three gyro outputs through misalignment and per-axis error models.
#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "sensor/gyro_sensor.h"
#include "sensor/sensor_config.h"

namespace gyrosid {
namespace {

using namespace units;

Excitation tumbling(std::size_t n) {
  Excitation ex;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 0.1 * k;
    ex.t_s.push_back(t);
    ex.omega_ib_b.push_back(Eigen::Vector3d(std::sin(t), 0.5 * std::cos(0.3 * t), -0.2 + 0.1 * t / n));
    ex.f_b.push_back(Eigen::Vector3d(1.0, -2.0, 9.0));
    ex.chamber_temp_c.push_back(20);
    ex.probe_temp_c.push_back(20);
    ex.coil_temp_c.push_back(20 + 0.01 * t);
    ex.coil_temp_rate_c_per_s.push_back(0.01);
  }
  return ex;
}

TEST(Triad, ErrorFreeGyrosMeasureTheMisalignedInputAxes) {
  TriadSensor t;
  t.alignment = {GyroAlignment{1e-3, -2e-3, 0.5e-3, 0.1e-3}, GyroAlignment{-1e-3, 0.3e-3, 2e-3, -0.4e-3},
                 GyroAlignment{0.7e-3, 0.2e-3, -1e-3, 1.5e-3}};
  const Excitation ex = tumbling(500);
  const TriadOutput out = simulate_triad(t, ex, 1);
  const Eigen::Matrix3d m = measurement_matrix(t.alignment);
  for (std::size_t k = 0; k < ex.size(); ++k) {
    const Eigen::Vector3d expected = m * ex.omega_ib_b[k];
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(out.gyro[i].rate_radps[k], expected(i), 1e-15);
  }
}

TEST(Triad, EachGyroSeesSpecificForceInItsOwnAxes) {
  TriadSensor t;
  for (auto& g : t.gyros) g.errors.g_sensitivity = Eigen::Vector3d(0, 0, dph_to_radps(1.0));  // along its input axis
  const Excitation ex = tumbling(3);
  const TriadOutput out = simulate_triad(t, ex, 1);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(out.gyro[i].rate_radps[0] - ex.omega_ib_b[0](i), dph_to_radps(1.0) * ex.f_b[0](i), 1e-15);
  }
}

TEST(Triad, AxesDrawIndependentNoiseDeterministically) {
  TriadSensor t;
  for (auto& g : t.gyros) g.noise.arw_rad_rt_s = 1e-3;
  Excitation ex = tumbling(20000);
  for (auto& w : ex.omega_ib_b) w.setZero();
  const TriadOutput a = simulate_triad(t, ex, 7), b = simulate_triad(t, ex, 7);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a.gyro[i].rate_radps, b.gyro[i].rate_radps);
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t k = 0; k < ex.size(); ++k) {
    const double x = a.gyro[0].rate_radps[k], y = a.gyro[1].rate_radps[k];
    sxy += x * y;
    sxx += x * x;
    syy += y * y;
  }
  EXPECT_LT(std::abs(sxy / std::sqrt(sxx * syy)), 4.0 / std::sqrt(20000.0));  // |rho| < 4 sigma
}

TEST(Triad, ConfigLoadsAxesAndMilliradianAngles) {
  const auto spec = load_sensor_file("builtin:sensors/fog_triad.yaml");
  const TriadSensor& t = std::get<TriadSensor>(spec);
  EXPECT_NEAR(t.alignment[0].ia_x, 0.8e-3, 1e-15);
  EXPECT_NEAR(t.alignment[2].insertion_y, -0.3e-3, 1e-15);
  EXPECT_NEAR(radps_to_dph(t.gyros[1].errors.bias_radps), -15.0, 1e-12);
  EXPECT_DOUBLE_EQ(t.thermal.tau_s, 300.0);
}

}  // namespace
}  // namespace gyrosid
