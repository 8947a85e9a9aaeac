#include "model/triad_angles.h"

#include <Eigen/Dense>

#include <cmath>

#include "core/error.h"
#include "core/triad_axes.h"
#include "sensor/misalignment.h"

namespace gyrosid {
namespace {

// Thesis names per gyro: IA->RA (phi, theta, psi), insertion (mu, eta, xi); each with _x and _y.
constexpr const char* kIa[] = {"phi", "theta", "psi"};
constexpr const char* kInsertion[] = {"mu", "eta", "xi"};

double& angle_ref(std::array<GyroAlignment, 3>& a, int k) {
  GyroAlignment& g = a[static_cast<std::size_t>(k / 4)];
  switch (k % 4) {
    case 0: return g.ia_x;
    case 1: return g.ia_y;
    case 2: return g.insertion_x;
    default: return g.insertion_y;
  }
}

// d vec(M) / d angles at zero, by central differences of the exact chain (9 x 12; rows i*3+j).
Eigen::Matrix<double, 9, 12> first_order_map() {
  Eigen::Matrix<double, 9, 12> a;
  const double h = 1e-6;
  for (int k = 0; k < 12; ++k) {
    std::array<GyroAlignment, 3> plus{}, minus{};
    angle_ref(plus, k) = h;
    angle_ref(minus, k) = -h;
    const Eigen::Matrix3d d = (measurement_matrix(plus) - measurement_matrix(minus)) / (2 * h);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i * 3 + j, k) = std::round(d(i, j) * 1e6) / 1e6;  // exact 0, +-1
  }
  return a;
}

}  // namespace

AngleObservability analyse_angles(const std::array<std::array<bool, 3>, 3>& known) {
  AngleObservability out;
  for (int g = 0; g < 3; ++g) {
    out.angles.push_back(str_cat(kIa[g], "_x"));
    out.angles.push_back(str_cat(kIa[g], "_y"));
    out.angles.push_back(str_cat(kInsertion[g], "_x"));
    out.angles.push_back(str_cat(kInsertion[g], "_y"));
  }
  const Eigen::Matrix<double, 9, 12> a = first_order_map();
  Eigen::MatrixXd rows(0, 12);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      AngleObservability::Combination c;
      c.entry = str_cat("M_", kTriadAxes[i], kTriadAxes[j]);
      for (int k = 0; k < 12; ++k) {
        const double v = a(i * 3 + j, k);
        if (v == 0) continue;
        const bool first = c.expression.empty();
        c.expression += str_cat(first ? (v < 0 ? "-" : "") : (v < 0 ? " - " : " + "), out.angles[static_cast<std::size_t>(k)]);
      }
      c.observable = known[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      if (c.observable) {
        rows.conservativeResize(rows.rows() + 1, Eigen::NoChange);
        rows.bottomRows(1) = a.row(i * 3 + j);
      }
      out.combinations.push_back(std::move(c));
    }
  }
  // An angle alone is observable when its unit vector lies in the row space of the determined entries.
  Eigen::MatrixXd basis;
  if (rows.rows() > 0) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeFullV);
    out.rank = static_cast<int>((svd.singularValues().array() > 1e-9).count());
    basis = svd.matrixV().leftCols(out.rank);
  }
  for (int k = 0; k < 12; ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(12, k);
    const double residual = out.rank > 0 ? (e - basis * (basis.transpose() * e)).norm() : 1.0;
    out.angle_observable.push_back(residual < 1e-9);
  }
  return out;
}

}  // namespace gyrosid
