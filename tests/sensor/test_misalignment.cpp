// The misalignment chain (thesis s3.4): exact rotations against eq 3.13 and the small-angle matrix of
// eq 3.72, which must agree to second order in the angles.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "sensor/misalignment.h"

namespace gyrosid {
namespace {

std::array<GyroAlignment, 3> scaled(double eps) {
  // Distinct angles for every gyro and stage, all of order eps.
  return {GyroAlignment{0.8 * eps, -0.5 * eps, 0.3 * eps, 0.4 * eps}, GyroAlignment{-0.6 * eps, 0.9 * eps, -0.2 * eps, 0.5 * eps},
          GyroAlignment{0.4 * eps, 0.7 * eps, 0.6 * eps, -0.3 * eps}};
}

TEST(Misalignment, InputAxisInReferenceAxesIsEquation313) {
  const double tx = 0.03, ty = -0.07;
  const Eigen::Vector3d u = ra_from_ia(tx, ty) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(u.x(), std::sin(ty), 1e-15);
  EXPECT_NEAR(u.y(), -std::sin(tx) * std::cos(ty), 1e-15);
  EXPECT_NEAR(u.z(), std::cos(tx) * std::cos(ty), 1e-15);
}

TEST(Misalignment, ClusterOrientationsAreProperRotationsOntoEachAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Matrix3d p = ca_from_ra(axis);
    EXPECT_NEAR(p.determinant(), 1.0, 1e-15);
    EXPECT_TRUE((p * p.transpose()).isIdentity(1e-15));
    EXPECT_TRUE((p * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::Unit(axis)));
  }
}

TEST(Misalignment, ExactChainAgreesWithEquation372ToSecondOrder) {
  // |M_exact - M_small| = O(eps^2): bounded by C eps^2 and shrinking fourfold when eps halves.
  double previous = 0;
  for (double eps : {4e-3, 2e-3, 1e-3, 5e-4}) {
    const double err = (measurement_matrix(scaled(eps)) - measurement_matrix_small_angle(scaled(eps))).cwiseAbs().maxCoeff();
    EXPECT_LT(err, 2.0 * eps * eps) << "eps " << eps;
    if (previous > 0) {
      EXPECT_NEAR(previous / err, 4.0, 0.1);
    }
    previous = err;
    // And the first-order terms are really there: M_small - I is of order eps.
    EXPECT_GT((measurement_matrix_small_angle(scaled(eps)) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 0.5 * eps);
  }
}

TEST(Misalignment, OnlyTheSumsOfInputAndInsertionAnglesAreObservableToFirstOrder) {
  auto a = scaled(1e-3);
  auto b = a;
  for (auto& g : b) {
    std::swap(g.ia_x, g.insertion_x);
    std::swap(g.ia_y, g.insertion_y);
  }
  EXPECT_TRUE(measurement_matrix_small_angle(a).isApprox(measurement_matrix_small_angle(b), 1e-15));
  EXPECT_LT((measurement_matrix(a) - measurement_matrix(b)).cwiseAbs().maxCoeff(), 2e-6);
}

TEST(Misalignment, NoAnglesGiveTheIdentityAndRowsAreUnitVectors) {
  EXPECT_TRUE(measurement_matrix({}).isIdentity(1e-15));
  const Eigen::Matrix3d m = measurement_matrix(scaled(0.05));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.row(i).norm(), 1.0, 1e-14);
}

}  // namespace
}  // namespace gyrosid
