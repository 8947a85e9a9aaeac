// The Gaussian node of the RBF network with a width per input (thesis eqs 4.1-4.3), written once:
//
//   phi(x) = exp(-z),   z = sum_k u_k^2,   u_k = (x_k - c_k) / r_k                       (normalised units)
//
// templated on the scalar of the centre and width so it evaluates on double and on ceres::Jet (automatic
// differentiation, used to check the analytic derivatives), as Sophus templates its groups. The joint solvers
// (ceres, ipopt) iterate a packed block per node, [c_1..c_d, rho_1..rho_d, w] with rho_k = log r_k so widths
// stay positive; NodeBlock names its parts, and node_output() gives w phi with its analytic gradient
//   d(w phi)/dc_k = w phi 2 u_k / r_k,   d(w phi)/drho_k = w phi 2 u_k^2,   d(w phi)/dw = phi.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace gyrosid {

// phi(x) for centre c and widths r read every `stride` entries (stride = m for column-major node matrices).
template <typename T>
T gaussian(const double* x, const T* c, const T* r, Eigen::Index d, Eigen::Index stride = 1) {
  using std::exp;
  T z(0.0);
  for (Eigen::Index k = 0; k < d; ++k) {
    const T u = (x[k] - c[k * stride]) / r[k * stride];
    z += u * u;
  }
  return exp(-z);
}

// One node's packed parameter block [c_1..c_d, rho_1..rho_d, w]; T is double or const double.
template <typename T>
struct NodeBlock {
  T* data;
  Eigen::Index d;

  static constexpr Eigen::Index size(Eigen::Index dimension) { return 2 * dimension + 1; }
  static constexpr Eigen::Index dimension_of(Eigen::Index size) { return (size - 1) / 2; }
  static constexpr Eigen::Index weight_index(Eigen::Index dimension) { return 2 * dimension; }
  T* centre() const { return data; }
  T* log_width() const { return data + d; }
  T& weight() const { return data[weight_index(d)]; }
};

// w phi(x) of one packed node; fills gradient[0..2d] (d/dc, d/drho, d/dw) when it is not null.
double node_output(const double* x, NodeBlock<const double> node, double* gradient);

// Gaussian columns (N x M): column j is phi for centre row j of `centres` and width row j of `widths`
// (both M x d). Split across threads by column; no N x N matrix.
Eigen::MatrixXd gaussian_columns(const Eigen::MatrixXd& x, const Eigen::MatrixXd& centres, const Eigen::MatrixXd& widths);
// The same with one width row for every centre.
Eigen::MatrixXd gaussian_columns(const Eigen::MatrixXd& x, const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths);

}  // namespace gyrosid
