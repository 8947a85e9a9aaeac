// Distribution functions against published table values (Abramowitz & Stegun Tables 26.1 / 26.8; every
// statistics text's chi-square table).
#include <gtest/gtest.h>

#include <cmath>

#include "core/stats.h"

namespace gyrosid::stats {
namespace {

TEST(Stats, NormalQuantilesMatchTables) {
  EXPECT_NEAR(normal_quantile(0.975), 1.959963985, 1e-8);
  EXPECT_NEAR(normal_quantile(0.95), 1.644853627, 1e-8);
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(normal_quantile(1e-6), -4.753424309, 1e-7);
  EXPECT_NEAR(normal_cdf(1.0), 0.841344746, 1e-9);
}

TEST(Stats, ChiSquareQuantilesMatchTables) {
  EXPECT_NEAR(chi2_quantile(0.95, 1), 3.841459, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.95, 10), 18.307038, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.05, 10), 3.940299, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.975, 30), 46.979242, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.01, 100), 70.064895, 1e-4);
  EXPECT_NEAR(chi2_quantile(0.5, 2), 2.0 * std::log(2.0), 1e-10);  // median of chi2(2) = 2 ln 2 exactly
}

TEST(Stats, ChiSquareCdfInvertsQuantile) {
  for (double dof : {0.7, 1.0, 3.5, 12.0, 250.0}) {
    for (double p : {0.001, 0.1, 0.5, 0.9, 0.999}) {
      EXPECT_NEAR(chi2_cdf(chi2_quantile(p, dof), dof), p, 1e-10) << "dof " << dof << " p " << p;
    }
  }
  // chi2 with 2 dof is exponential: CDF = 1 - exp(-x/2).
  EXPECT_NEAR(chi2_cdf(3.0, 2.0), 1.0 - std::exp(-1.5), 1e-14);
}

}  // namespace
}  // namespace gyrosid::stats
