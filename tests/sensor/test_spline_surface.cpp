// The bicubic spline surface: exact for bicubic polynomials (the not-a-knot spline reproduces cubics),
// interpolating at the grid, explicit outside-grid policy.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "sensor/spline_surface.h"

namespace gyrosid {
namespace {

// p(x, y) = sum_{i,j<=3} a_ij x^i y^j with fixed coefficients.
double poly(double x, double y, double* dy = nullptr) {
  const double a[4][4] = {{0.3, -1.2, 0.5, 0.02}, {0.7, 0.1, -0.03, 0.004}, {-0.05, 0.02, 0.001, -0.0002}, {0.001, -0.0004, 0.00002, 0.000003}};
  double v = 0, d = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      v += a[i][j] * std::pow(x, i) * std::pow(y, j);
      if (j > 0) d += a[i][j] * std::pow(x, i) * j * std::pow(y, j - 1);
    }
  if (dy) *dy = d;
  return v;
}

SplineSurface poly_surface(OutsideGridPolicy policy) {
  const std::vector<double> x{-20, 0, 20, 25, 40, 60};  // the thesis's non-uniform temperature grid
  const std::vector<double> y{-10, -8, -6, -4, -2, -1, 1, 2, 4, 6, 8, 10};
  Eigen::MatrixXd v(x.size(), y.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < y.size(); ++j) v(i, j) = poly(x[i], y[j]);
  return SplineSurface(x, y, v, policy);
}

TEST(SplineSurface, ReproducesBicubicPolynomialsExactly) {
  const SplineSurface s = poly_surface(OutsideGridPolicy::error);
  RandomStream r(3, "points");
  for (int k = 0; k < 2000; ++k) {
    const double x = -20 + 80 * r.uniform(), y = -10 + 20 * r.uniform();
    double dy = 0;
    const double expected = poly(x, y, &dy);
    const SurfaceSample got = s(x, y);
    EXPECT_NEAR(got.value, expected, 1e-9 * (1 + std::abs(expected))) << x << ", " << y;
    EXPECT_NEAR(got.d_dy, dy, 1e-9 * (1 + std::abs(dy)));
    EXPECT_FALSE(got.clamped);
  }
}

TEST(SplineSurface, InterpolatesTheGridValues) {
  const std::vector<double> x{0, 1, 3}, y{0, 2, 3, 7, 8};
  Eigen::MatrixXd v(3, 5);
  v << 1, -2, 3, 0.5, 4, 2, 7, -1, 0, 1, -3, 2, 2, 5, 0;  // arbitrary, not smooth
  const SplineSurface s(x, y, v, OutsideGridPolicy::error);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 5; ++j) EXPECT_NEAR(s(x[i], y[j]).value, v(i, j), 1e-12);
}

TEST(SplineSurface, SlopeOperatorIsExactForCubicsAndLowOrders) {
  const std::vector<double> x{-3, -1, 0.5, 2, 2.5, 6};
  const Eigen::MatrixXd d = spline_slope_operator(x);
  Eigen::VectorXd y(6), dy(6);
  for (int i = 0; i < 6; ++i) {
    y(i) = 2 - x[i] + 0.5 * x[i] * x[i] - 0.1 * x[i] * x[i] * x[i];
    dy(i) = -1 + x[i] - 0.3 * x[i] * x[i];
  }
  EXPECT_LT((d * y - dy).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::MatrixXd d3 = spline_slope_operator({0, 1, 3});  // parabola through 3 points
  EXPECT_NEAR((d3 * Eigen::Vector3d(0, 1, 9))(2), 6.0, 1e-12);   // y = x^2
  const Eigen::MatrixXd d2 = spline_slope_operator({1, 3});      // straight line
  EXPECT_NEAR((d2 * Eigen::Vector2d(1, 5))(0), 2.0, 1e-15);
}

TEST(SplineSurface, OutsidePolicyIsExplicit) {
  const SplineSurface strict = poly_surface(OutsideGridPolicy::error);
  try {
    strict(61.0, 0.0);
    FAIL() << "extrapolated silently";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("outside the grid [-20, 60]"));
  }
  const SplineSurface clamp = poly_surface(OutsideGridPolicy::clamp);
  const SurfaceSample edge = clamp(80.0, 3.0);
  EXPECT_TRUE(edge.clamped);
  EXPECT_NEAR(edge.value, poly(60.0, 3.0), 1e-9);
  EXPECT_EQ(edge.d_dx, 0.0);
  EXPECT_FALSE(clamp(60.0, 3.0).clamped);
}

TEST(SplineSurface, RejectsBadGrids) {
  EXPECT_THROW(SplineSurface({0, 1, 1}, {0, 1}, Eigen::MatrixXd::Zero(3, 2), OutsideGridPolicy::error), Error);
  EXPECT_THROW(SplineSurface({0, 1}, {0, 1}, Eigen::MatrixXd::Zero(3, 2), OutsideGridPolicy::error), Error);
}

}  // namespace
}  // namespace gyrosid
