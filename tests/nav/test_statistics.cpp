// Anderson-Darling normality test against an independent implementation (scipy.stats.anderson, SciPy 1.10.1,
// which reports the unadjusted A^2) and against its nominal 5 % size.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "nav/statistics.h"

namespace gyrosid::nav {
namespace {

TEST(AndersonDarling, MatchesScipy) {
  // scipy.stats.anderson([...], 'norm').statistic, computed once with SciPy 1.10.1.
  const std::vector<double> x{2.3, -0.7, 1.1, 0.4, -1.9, 0.8, 3.1, -0.2, 0.05, 1.7, -1.1, 0.9, 2.2, -0.45, 0.6, 1.3};
  EXPECT_NEAR(anderson_darling_normal(x).a2, 0.08073427876306027, 1e-12);
  const std::vector<double> outlier{0.1, 0.2, 0.15, 0.3, 5.0, 0.25, 0.12, 0.18, 0.22, 0.3, 0.11, 0.16};
  const AndersonDarling a = anderson_darling_normal(outlier);
  EXPECT_NEAR(a.a2, 3.5732891266705487, 1e-12);
  EXPECT_FALSE(a.normal_at_5_percent);
  EXPECT_LT(a.p_value, 0.01);
}

TEST(AndersonDarling, RejectsNormalSamplesAtItsNominalRateAndSkewedOnesOften) {
  int rejected_normal = 0, rejected_exponential = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    RandomStream r(static_cast<std::uint64_t>(t), "ad");
    std::vector<double> normal(50), expo(50);
    for (auto& v : normal) v = r.normal(3.0, 2.0);
    for (auto& v : expo) v = -std::log(r.uniform());
    rejected_normal += !anderson_darling_normal(normal).normal_at_5_percent;
    rejected_exponential += !anderson_darling_normal(expo).normal_at_5_percent;
  }
  EXPECT_NEAR(static_cast<double>(rejected_normal) / trials, 0.05, 0.015);  // binomial sd 0.005
  EXPECT_GT(static_cast<double>(rejected_exponential) / trials, 0.9);
}

}  // namespace
}  // namespace gyrosid::nav
