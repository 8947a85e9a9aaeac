// Exact thermal lag against closed-form responses of first-order systems to a ramp.
#include <gtest/gtest.h>

#include <cmath>

#include "core/thermal_lag.h"

namespace gyrosid {
namespace {

// Chamber: 20 C until t0, then ramping at s C/s.
PiecewiseLinear ramp_input(double t0, double s, double t_end) {
  PiecewiseLinear p;
  p.append(0.0, 20.0);
  p.append(t0, 20.0);
  p.append(t_end, 20.0 + s * (t_end - t0));
  return p;
}

TEST(ThermalLag, SingleStageFollowsTheClosedFormRampResponse) {
  const double tau = 300.0, s = 5.0 / 60.0, t0 = 100.0;
  std::vector<double> q;
  for (double t = 0; t <= 3000; t += 7.3) q.push_back(t);  // query grid unaligned with the knot at t0
  const auto r = thermal_lag_response({0.0, {tau}}, ramp_input(t0, s, 4000), q);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double u = std::max(0.0, q[i] - t0);
    const double expected = 20.0 + s * (u - tau * (1.0 - std::exp(-u / tau)));  // y = s(t - tau(1 - e^-t/tau))
    EXPECT_NEAR(r.stage[0][i], expected, 1e-10) << "t = " << q[i];
    EXPECT_NEAR(r.output_rate[i], s * (1.0 - std::exp(-u / tau)), 1e-12);
  }
}

TEST(ThermalLag, DelayShiftsTheResponse) {
  const double tau = 120.0, s = 0.1, delay = 45.0;
  std::vector<double> q{0, 50, 100, 145, 200, 500, 1000};
  const auto delayed = thermal_lag_response({delay, {tau}}, ramp_input(100, s, 2000), q);
  std::vector<double> shifted;
  for (double t : q) shifted.push_back(t - delay);
  const auto plain = thermal_lag_response({0.0, {tau}}, ramp_input(100, s, 2000), {-45, 5, 55, 100, 155, 455, 955});
  for (std::size_t i = 0; i < q.size(); ++i) EXPECT_NEAR(delayed.stage[0][i], plain.stage[0][i], 1e-10);
}

TEST(ThermalLag, TwoStagesFollowTheClosedForm) {
  // Ramp from rest through two lags tau1 != tau2:
  // y2 = s (t - tau1 - tau2 + (tau1^2 e^{-t/tau1} - tau2^2 e^{-t/tau2}) / (tau1 - tau2)).
  const double t1 = 200.0, t2 = 80.0, s = 0.05;
  std::vector<double> q;
  for (double t = 0; t <= 2500; t += 11.0) q.push_back(t);
  const auto r = thermal_lag_response({0.0, {t1, t2}}, ramp_input(0.0, s, 3000), q);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double t = q[i];
    const double y1 = 20.0 + s * (t - t1 + t1 * std::exp(-t / t1));
    const double y2 = 20.0 + s * (t - t1 - t2 + (t1 * t1 * std::exp(-t / t1) - t2 * t2 * std::exp(-t / t2)) / (t1 - t2));
    EXPECT_NEAR(r.stage[0][i], y1, 1e-10);
    EXPECT_NEAR(r.stage[1][i], y2, 1e-10);
    EXPECT_NEAR(r.output_rate[i], (y1 - y2) / t2, 1e-12);
  }
}

TEST(ThermalLag, ZeroStagesPassThroughAndRateIsTheInputSlope) {
  const auto r = thermal_lag_response({0.0, {0.0}}, ramp_input(10, 0.2, 100), {0, 5, 20, 50});
  EXPECT_DOUBLE_EQ(r.stage[0][2], 22.0);
  EXPECT_DOUBLE_EQ(r.output_rate[0], 0.0);
  EXPECT_DOUBLE_EQ(r.output_rate[2], 0.2);
}

TEST(ThermalLag, CoarseAndFineQueriesAgree) {
  // Exactness: the state at t = 600 s does not depend on how many intermediate queries were made.
  const PiecewiseLinear in = ramp_input(33.3, 0.07, 5000);
  std::vector<double> fine;
  for (int i = 0; i <= 6000; ++i) fine.push_back(0.1 * i);
  const auto a = thermal_lag_response({12.0, {250.0, 40.0}}, in, fine);
  const auto b = thermal_lag_response({12.0, {250.0, 40.0}}, in, {600.0});
  EXPECT_NEAR(a.stage[1].back(), b.stage[1][0], 1e-10);
}

}  // namespace
}  // namespace gyrosid
