// A smooth 2-D surface interpolated bicubically from values on a rectilinear (possibly non-uniform) grid -
// the thesis's scale-factor error map (figs 3.5/3.6, built with Matlab's interp2 'spline').
//
// The interpolant is the tensor-product cubic spline with not-a-knot end conditions (Matlab's 'spline'):
// each grid cell is a bicubic Hermite patch whose corner values f, f_x, f_y, f_xy come from 1-D splines
// along the grid lines. It reproduces any polynomial of degree <= 3 in each variable exactly.
//
// Outside the grid the policy is explicit: `error` throws, `clamp` evaluates at the nearest grid point on
// the boundary and reports that it did (callers count the warnings). Never silent extrapolation.
#pragma once

#include <Eigen/Dense>

#include <array>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"

namespace gyrosid {

enum class OutsideGridPolicy { error, clamp };

template <>
struct EnumNames<OutsideGridPolicy> {
  static constexpr std::string_view kNoun = "outside-grid policy";
  static constexpr std::array<std::pair<OutsideGridPolicy, std::string_view>, 2> kTable{
      {{OutsideGridPolicy::error, "error"}, {OutsideGridPolicy::clamp, "clamp"}}};
};

// Slopes at the knots of the not-a-knot cubic spline through (x_i, y_i) are D * y; returns D (n x n).
// n = 2 gives the straight line, n = 3 the parabola through the three points.
Eigen::MatrixXd spline_slope_operator(const std::vector<double>& x);

struct SurfaceSample {
  double value = 0.0;
  double d_dx = 0.0;
  double d_dy = 0.0;
  bool clamped = false;  // the point was outside the grid and the clamp policy applied
};

class SplineSurface {
 public:
  SplineSurface() = default;
  // values(i, j) at (x[i], y[j]); x and y strictly increasing with at least two points each.
  SplineSurface(std::vector<double> x, std::vector<double> y, const Eigen::MatrixXd& values,
                OutsideGridPolicy outside);

  SurfaceSample operator()(double x, double y) const;
  bool contains(double x, double y) const;

  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }
  const Eigen::MatrixXd& values() const { return f_; }
  // Hermite corner data: slopes along x and y and the cross derivative at every grid point.
  const Eigen::MatrixXd& d_dx() const { return fx_; }
  const Eigen::MatrixXd& d_dy() const { return fy_; }
  const Eigen::MatrixXd& d2_dxdy() const { return fxy_; }
  OutsideGridPolicy outside() const { return outside_; }

 private:
  std::vector<double> x_, y_;
  Eigen::MatrixXd f_, fx_, fy_, fxy_;
  OutsideGridPolicy outside_ = OutsideGridPolicy::error;
};

}  // namespace gyrosid
