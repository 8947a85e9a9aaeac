// Distribution functions against published table values (Abramowitz & Stegun Tables 26.1 / 26.8; every
// statistics text's chi-square table).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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

TEST(Stats, StudentTTailsMatchClosedFormsAndTables) {
  for (double t : {0.0, 0.3, 1.0, 2.5, 12.706, 300.0}) {
    EXPECT_NEAR(student_t_two_sided(t, 1.0), 1.0 - 2.0 / std::numbers::pi * std::atan(t), 1e-13) << t;  // Cauchy
    EXPECT_NEAR(student_t_two_sided(t, 2.0), 1.0 - t / std::sqrt(2.0 + t * t), 1e-13) << t;
  }
  // Two-sided 5 % and 1 % points (any t table): 2.5706 and 4.0321 at 5 dof, 2.2281 and 3.1693 at 10, 2.0096 at 49.
  EXPECT_NEAR(student_t_two_sided(2.570582, 5.0), 0.05, 1e-6);
  EXPECT_NEAR(student_t_two_sided(4.032143, 5.0), 0.01, 1e-6);
  EXPECT_NEAR(student_t_two_sided(2.228139, 10.0), 0.05, 1e-6);
  EXPECT_NEAR(student_t_two_sided(3.169273, 10.0), 0.01, 1e-6);
  EXPECT_NEAR(student_t_two_sided(2.009575, 49.0), 0.05, 1e-6);
  // Many degrees of freedom: the normal's tail.
  EXPECT_NEAR(student_t_two_sided(1.959964, 1e7), 0.05, 1e-6);
  // I_x(a, 1) = x^a and the symmetry I_x(a, b) = 1 - I_{1-x}(b, a) on both sides of the switch.
  EXPECT_NEAR(regularized_beta(2.5, 1.0, 0.3), std::pow(0.3, 2.5), 1e-14);
  EXPECT_NEAR(regularized_beta(3.0, 0.5, 0.9) + regularized_beta(0.5, 3.0, 0.1), 1.0, 1e-13);
}

}  // namespace
}  // namespace gyrosid::stats
