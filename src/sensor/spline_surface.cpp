#include "sensor/spline_surface.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace gyrosid {

Eigen::MatrixXd spline_slope_operator(const std::vector<double>& x) {
  const int n = static_cast<int>(x.size());
  if (n < 2) fail("spline: need at least two knots, got ", n);
  for (int i = 1; i < n; ++i)
    if (!(x[i] > x[i - 1])) fail("spline: knots must be strictly increasing (", x[i - 1], ", ", x[i], ")");
  std::vector<double> h(n - 1);
  for (int i = 0; i + 1 < n; ++i) h[i] = x[i + 1] - x[i];

  // Second derivatives M = S y from the tridiagonal continuity equations plus end conditions, then
  // slopes y'_i from the cubic on each interval. Build column by column (y = unit vectors): n is small.
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, n);  // rhs = R y
  for (int i = 1; i + 1 < n; ++i) {
    system(i, i - 1) = h[i - 1];
    system(i, i) = 2.0 * (h[i - 1] + h[i]);
    system(i, i + 1) = h[i];
    rhs(i, i + 1) = 6.0 / h[i];
    rhs(i, i) = -6.0 / h[i] - 6.0 / h[i - 1];
    rhs(i, i - 1) = 6.0 / h[i - 1];
  }
  if (n == 2) {  // straight line: M = 0
    system(0, 0) = 1.0;
    system(1, 1) = 1.0;
  } else if (n == 3) {  // single parabola: M constant
    system(0, 0) = 1.0;
    system(0, 1) = -1.0;
    system(2, 1) = -1.0;
    system(2, 2) = 1.0;
  } else {  // not-a-knot: third derivative continuous at x_1 and x_{n-2}
    system(0, 0) = h[1];
    system(0, 1) = -(h[0] + h[1]);
    system(0, 2) = h[0];
    system(n - 1, n - 3) = h[n - 2];
    system(n - 1, n - 2) = -(h[n - 3] + h[n - 2]);
    system(n - 1, n - 1) = h[n - 3];
  }
  const Eigen::MatrixXd second = system.fullPivLu().solve(rhs);  // M = second * y

  Eigen::MatrixXd slope = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i + 1 < n; ++i) {
    // y'_i = (y_{i+1} - y_i)/h_i - h_i (2 M_i + M_{i+1}) / 6
    slope(i, i + 1) += 1.0 / h[i];
    slope(i, i) -= 1.0 / h[i];
    slope.row(i) -= h[i] * (2.0 * second.row(i) + second.row(i + 1)) / 6.0;
  }
  // y'_{n-1} = (y_{n-1} - y_{n-2})/h + h (M_{n-2} + 2 M_{n-1}) / 6
  const double hl = h[n - 2];
  slope(n - 1, n - 1) += 1.0 / hl;
  slope(n - 1, n - 2) -= 1.0 / hl;
  slope.row(n - 1) += hl * (second.row(n - 2) + 2.0 * second.row(n - 1)) / 6.0;
  return slope;
}

SplineSurface::SplineSurface(std::vector<double> x, std::vector<double> y, const Eigen::MatrixXd& values,
                             OutsideGridPolicy outside)
    : x_(std::move(x)), y_(std::move(y)), f_(values), outside_(outside) {
  if (f_.rows() != static_cast<Eigen::Index>(x_.size()) || f_.cols() != static_cast<Eigen::Index>(y_.size())) {
    fail("spline surface: values are ", f_.rows(), " x ", f_.cols(), " but the grid is ", x_.size(), " x ",
         y_.size());
  }
  const Eigen::MatrixXd dx = spline_slope_operator(x_);
  const Eigen::MatrixXd dy = spline_slope_operator(y_);
  fx_ = dx * f_;               // d/dx along each column (fixed y)
  fy_ = f_ * dy.transpose();   // d/dy along each row (fixed x)
  fxy_ = fx_ * dy.transpose(); // d2/dxdy: spline in y of the x-slopes
}

bool SplineSurface::contains(double x, double y) const {
  return x >= x_.front() && x <= x_.back() && y >= y_.front() && y <= y_.back();
}

namespace {

// Cell index and local coordinate u in [0, 1] for `v` on knots `k` (v already inside the range).
std::pair<std::size_t, double> locate(const std::vector<double>& k, double v) {
  std::size_t i = static_cast<std::size_t>(std::upper_bound(k.begin(), k.end(), v) - k.begin());
  i = std::clamp<std::size_t>(i, 1, k.size() - 1) - 1;
  return {i, (v - k[i]) / (k[i + 1] - k[i])};
}

// Cubic Hermite basis and derivatives at u: [h00, h01, h10, h11] (value/value/slope/slope weights).
std::array<double, 4> hermite(double u) {
  const double u2 = u * u, u3 = u2 * u;
  return {2 * u3 - 3 * u2 + 1, -2 * u3 + 3 * u2, u3 - 2 * u2 + u, u3 - u2};
}
std::array<double, 4> hermite_derivative(double u) {
  const double u2 = u * u;
  return {6 * u2 - 6 * u, -6 * u2 + 6 * u, 3 * u2 - 4 * u + 1, 3 * u2 - 2 * u};
}

}  // namespace

SurfaceSample SplineSurface::operator()(double x, double y) const {
  SurfaceSample s;
  const bool x_outside = x < x_.front() || x > x_.back();
  const bool y_outside = y < y_.front() || y > y_.back();
  if (x_outside || y_outside || std::isnan(x) || std::isnan(y)) {
    if (outside_ == OutsideGridPolicy::error || std::isnan(x) || std::isnan(y)) {
      fail("spline surface: point (", x, ", ", y, ") is outside the grid [", x_.front(), ", ", x_.back(),
           "] x [", y_.front(), ", ", y_.back(), "] and the outside-grid policy is 'error'");
    }
    s.clamped = true;
    x = std::clamp(x, x_.front(), x_.back());
    y = std::clamp(y, y_.front(), y_.back());
  }
  // (Plain locals, not structured bindings: lambdas below capture them, which clang 14 does not allow.)
  const auto cell_x = locate(x_, x), cell_y = locate(y_, y);
  const std::size_t i = cell_x.first, j = cell_y.first;
  const double u = cell_x.second, v = cell_y.second;
  const double hx = x_[i + 1] - x_[i], hy = y_[j + 1] - y_[j];
  const auto bu = hermite(u), bv = hermite(v), du = hermite_derivative(u), dv = hermite_derivative(v);

  // Corner data in Hermite order: index 0/1 = value at the low/high knot, 2/3 = scaled slope there.
  auto corner = [&](int a, int b) {
    const std::size_t ii = i + (a & 1), jj = j + (b & 1);
    const double scale_x = a >= 2 ? hx : 1.0, scale_y = b >= 2 ? hy : 1.0;
    if (a < 2 && b < 2) return f_(ii, jj);
    if (a >= 2 && b < 2) return scale_x * fx_(ii, jj);
    if (a < 2) return scale_y * fy_(ii, jj);
    return scale_x * scale_y * fxy_(ii, jj);
  };
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      const double c = corner(a, b);
      s.value += bu[a] * bv[b] * c;
      s.d_dx += du[a] * bv[b] * c / hx;
      s.d_dy += bu[a] * dv[b] * c / hy;
    }
  }
  if (s.clamped) {
    // Held constant beyond the edge in the clamped direction.
    if (x_outside) s.d_dx = 0.0;
    if (y_outside) s.d_dy = 0.0;
  }
  return s;
}

}  // namespace gyrosid
