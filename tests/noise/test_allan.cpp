// Overlapping Allan deviation: analytic sequences, an independent brute-force implementation, the
// NIST SP 1065 degrees of freedom, and the noise-coefficient fit on exact model curves.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random.h"
#include "noise/allan.h"
#include "noise/state_space.h"

namespace gyrosid {
namespace {

const AllanPoint& at_m(const std::vector<AllanPoint>& curve, double dt, std::size_t m) {
  for (const auto& p : curve)
    if (std::llround(p.tau_s / dt) == static_cast<long long>(m)) return p;
  throw std::runtime_error("no such m");
}

TEST(Allan, RampHasDeviationMOverRootTwo) {
  // y_k = c k: adjacent cluster averages differ by c m exactly, so sigma(m) = c m / sqrt(2).
  std::vector<double> y(1000);
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = 0.25 * static_cast<double>(k);
  const auto curve = overlapping_allan_deviation(y, 0.5);
  for (std::size_t m : {1, 2, 5, 10, 100, 316}) EXPECT_NEAR(at_m(curve, 0.5, m).adev, 0.25 * m / std::sqrt(2.0), 1e-9);
}

TEST(Allan, AlternatingSequenceHasClosedFormDeviations) {
  // +1, -1, +1, ...: m = 1 -> sqrt(2); m even -> 0; m = 3 -> cluster means +-1/3 -> sqrt(2)/3.
  std::vector<double> y(600);
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = (k % 2 == 0) ? 1.0 : -1.0;
  const auto curve = overlapping_allan_deviation(y, 1.0, {.points_per_decade = 30});
  EXPECT_NEAR(at_m(curve, 1.0, 1).adev, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(at_m(curve, 1.0, 2).adev, 0.0, 1e-12);
  EXPECT_NEAR(at_m(curve, 1.0, 3).adev, std::sqrt(2.0) / 3.0, 1e-12);
}

TEST(Allan, AgreesWithBruteForceDefinition) {
  // Independent implementation: average every overlapping pair of adjacent clusters directly from the
  // samples (no phase, no running sums), O(n m) per tau.
  RandomStream r(5, "allan/brute");
  std::vector<double> y(3000);
  double walk = 0;
  for (double& v : y) {
    walk += 0.01 * r.normal();
    v = 3.0 + r.normal() + walk;  // offset + white + random walk
  }
  const double dt = 0.02;
  const auto curve = overlapping_allan_deviation(y, dt);
  for (const auto& p : curve) {
    const auto m = static_cast<std::size_t>(std::llround(p.tau_s / dt));
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t k = 0; k + 2 * m <= y.size(); ++k) {
      double a = 0, b = 0;
      for (std::size_t i = 0; i < m; ++i) {
        a += y[k + i];
        b += y[k + m + i];
      }
      const double d = (b - a) / static_cast<double>(m);
      sum += d * d;
      ++count;
    }
    EXPECT_NEAR(p.adev, std::sqrt(sum / (2.0 * count)), 1e-10 * p.adev) << "m = " << m;
    EXPECT_EQ(p.terms, count);
  }
}

TEST(Allan, WhiteFmDegreesOfFreedomFollowSp1065) {
  // NIST SP 1065 Table 5, white FM: edf = (3(N-1)/(2m) - 2(N-2)/N) * 4m^2/(4m^2+5); N = 1001, m = 10.
  const double n = 1001, m = 10;
  EXPECT_NEAR(allan_edf(0, n, m), (3 * (n - 1) / (2 * m) - 2 * (n - 2) / n) * (4 * m * m / (4 * m * m + 5)), 1e-12);
  EXPECT_NEAR(allan_edf(0, n, m), 146.18, 0.01);  // (150 - 1.996) * 400/405
  // Flicker FM with m = 1: 2(N-2)^2/(2.3N - 4.9), about 0.87 N.
  EXPECT_NEAR(allan_edf(-1, n, 1), 2 * (n - 2) * (n - 2) / (2.3 * n - 4.9), 1e-9);
  // Random-walk FM with m = 1: a = (N-2)/(N-3)^2, edf = a((N-1)^2 - 3(N-1) + 4) ~ N.
  EXPECT_NEAR(allan_edf(-2, n, 1), (n - 2) / ((n - 3) * (n - 3)) * ((n - 1) * (n - 1) - 3 * (n - 1) + 4), 1e-12);
}

TEST(Allan, ConfidenceIntervalsCoverTheTruthAtTheStatedRate) {
  // White noise, sigma(tau) = s/sqrt(tau/dt). Count how often the 68.3 % interval contains the truth.
  int covered = 0, total = 0;
  for (int seed = 0; seed < 40; ++seed) {
    RandomStream r(seed, "allan/coverage");
    std::vector<double> y(2000);
    for (double& v : y) v = r.normal();
    for (const auto& p : overlapping_allan_deviation(y, 1.0, {.points_per_decade = 3})) {
      const double truth = 1.0 / std::sqrt(p.tau_s);
      covered += (p.ci_low <= truth && truth <= p.ci_high);
      ++total;
    }
  }
  const double rate = static_cast<double>(covered) / total;
  EXPECT_GT(rate, 0.55);
  EXPECT_LT(rate, 0.85);
}

TEST(WhiteningModel, ProjectsAWhiteRandomWalkGaussMarkovCompositeExactly) {
  CompositeNoise c;
  c.white = 2.0, c.random_walk = 0.01, c.gauss_markov = {{3.0, 40.0}};
  const double dt = 0.5;
  const NoiseModel m = whitening_model(c, dt, dt, 2000.0);
  EXPECT_NEAR(m.white_var, 4.0 / dt, 1e-6 * 4.0 / dt);      // per-sample variance N^2 / dt
  EXPECT_NEAR(m.rw_q, 1e-4 * dt, 1e-6 * 1e-4 * dt);         // per-sample increment K^2 dt
  EXPECT_NEAR(m.gm_var, 9.0, 1e-4 * 9.0);
  EXPECT_NEAR(m.gm_tau_s, 40.0, 1e-3 * 40.0);
}

}  // namespace
}  // namespace gyrosid
