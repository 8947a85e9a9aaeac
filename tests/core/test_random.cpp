#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"

namespace gyrosid {
namespace {

TEST(RandomStream, SameSeedAndNameGiveIdenticalStreams) {
  RandomStream a(42, "gyro_x/arw"), b(42, "gyro_x/arw");
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next_u64(), b.next_u64());
  RandomStream c(42, "gyro_x/arw"), d(42, "gyro_x/arw");
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(c.normal(), d.normal());  // bit-identical
}

TEST(RandomStream, NamesAndSeedsSeparateStreams) {
  RandomStream a(42, "gyro_x/arw"), b(42, "gyro_y/arw"), c(43, "gyro_x/arw");
  int same_ab = 0, same_ac = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto x = a.next_u64();
    same_ab += x == b.next_u64();
    same_ac += x == c.next_u64();
  }
  EXPECT_EQ(same_ab, 0);
  EXPECT_EQ(same_ac, 0);
}

TEST(RandomStream, NormalHasUnitMomentsAndUniformIsOpen) {
  RandomStream r(7, "moments");
  const int n = 1000000;
  double sum = 0, sum2 = 0, sum4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.normal();
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));          // 5 sigma
  EXPECT_NEAR(var, 1.0, 5.0 * std::sqrt(2.0 / n));      // var of s^2 is 2/n
  EXPECT_NEAR(sum4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));  // kurtosis 3: Gaussian tails
  RandomStream u(7, "uniform");
  double lo = 1, hi = 0;
  for (int i = 0; i < n; ++i) {
    const double x = u.uniform();
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  EXPECT_GT(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_LT(lo, 1e-4);
  EXPECT_GT(hi, 1 - 1e-4);
}

}  // namespace
}  // namespace gyrosid
