#include "explain/linear_fit.h"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace gyrosid::explain {

WhitenedFit fit_whitened(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance) {
  WhitenedFit f;
  f.beta = Eigen::VectorXd::Zero(x.cols());
  f.kept.assign(static_cast<std::size_t>(x.cols()), 0);
  if (x.cols() == 0) {
    f.basis.resize(x.rows(), 0);
    f.residual = y;
    f.rss = y.squaredNorm();
    return f;
  }
  // Equilibrate the columns so that the rank decision does not depend on their units.
  Eigen::VectorXd norms = x.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < norms.size(); ++j) norms(j) = norms(j) > 0 ? norms(j) : 1.0;
  const Eigen::MatrixXd xs = x * norms.cwiseInverse().asDiagonal();
  // Two stages: a blocked Householder QR reduces the N x p columns to their p x p triangle (xs = Q1 R1); a
  // column-pivoted QR of that triangle decides the rank (R1 P = Q2 R2) - the decision pivoting xs itself
  // would make, since Q1 keeps every column's norm and every inner product - at a cost of O(N p^2) in
  // blocked (matrix-matrix) steps instead of O(N p^2) in rank-one updates.
  const Eigen::Index n = x.rows(), p = x.cols();
  Eigen::MatrixXd q1;
  Eigen::MatrixXd r1;
  if (n > p) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr1(xs);
    r1 = qr1.matrixQR().topRows(p).triangularView<Eigen::Upper>();
    q1 = qr1.householderQ() * Eigen::MatrixXd::Identity(n, p);
  } else {
    r1 = xs;
    q1 = Eigen::MatrixXd::Identity(n, n);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(r1.rows(), r1.cols());
  qr.setThreshold(tolerance);
  qr.compute(r1);
  f.rank = static_cast<int>(qr.rank());
  const Eigen::MatrixXd q = q1 * (qr.householderQ() * Eigen::MatrixXd::Identity(r1.rows(), f.rank));
  f.basis = q;
  // Coefficients of the kept (pivot) columns: R11 b = Q1' y.
  const Eigen::VectorXd qty = q.transpose() * y;
  const Eigen::VectorXd b = qr.matrixR().topLeftCorner(f.rank, f.rank).triangularView<Eigen::Upper>().solve(qty);
  for (int k = 0; k < f.rank; ++k) {
    const Eigen::Index col = qr.colsPermutation().indices()(k);
    f.beta(col) = b(k) / norms(col);
    f.kept[static_cast<std::size_t>(col)] = 1;
  }
  f.residual = y - q * qty;
  f.rss = f.residual.squaredNorm();
  return f;
}

namespace {

// The triangular factor of the Householder QR of a (n x m, n > m): row chunks that fit in cache, each
// stacked under the triangle of the chunks before it and reduced by Householder QR again (a sequential
// tall-skinny QR). Orthogonal transformations only, so as stable as one QR of a - the same R up to the
// signs of its rows - but every reflection runs over a chunk in cache instead of over all n rows in memory.
Eigen::MatrixXd triangular_factor(const Eigen::MatrixXd& a, Eigen::Index chunk = 512) {
  const Eigen::Index n = a.rows(), m = a.cols();
  Eigen::MatrixXd work(m + chunk, m);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr;
  Eigen::Index have = 0;  // rows of the running triangle at the top of work
  for (Eigen::Index start = 0; start < n; start += chunk) {
    const Eigen::Index b = std::min(chunk, n - start);
    work.middleRows(have, b) = a.middleRows(start, b);
    qr.compute(work.topRows(have + b));
    have = std::min(have + b, m);
    work.topRows(have) = qr.matrixQR().topRows(have).triangularView<Eigen::Upper>();
  }
  return work.topRows(m);
}

}  // namespace

double whitened_rss(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance) {
  return whitened_rss_and_rank(x, y, tolerance).rss;
}

RssAndRank whitened_rss_and_rank(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance) {
  const Eigen::Index n = x.rows(), p = x.cols();
  if (p == 0) return {y.squaredNorm(), 0};
  if (n <= p + 1) {
    const WhitenedFit f = fit_whitened(x, y, tolerance);
    return {f.rss, f.rank};
  }
  // The triangle of [X y] (X equilibrated): its last column holds Q1' y - the first p entries in the span of
  // X's columns, the last one the norm of the rest.
  Eigen::VectorXd norms = x.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < norms.size(); ++j) norms(j) = norms(j) > 0 ? norms(j) : 1.0;
  Eigen::MatrixXd xy(n, p + 1);
  xy.leftCols(p) = x * norms.cwiseInverse().asDiagonal();
  xy.col(p) = y;
  // Two row halves reduced at once (one per core of a two-core machine), then their stacked triangles: the
  // same R up to row signs as one sequential pass. The split does not depend on the thread count, so the
  // result is bit-identical with one thread or two.
  const Eigen::Index half = n / 2;
  Eigen::MatrixXd stacked(2 * (p + 1), p + 1);
  if (half > p + 1) {
    parallel_for(2, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
      for (std::ptrdiff_t k = begin; k < end; ++k) {
        stacked.middleRows(k * (p + 1), p + 1) = triangular_factor(k == 0 ? Eigen::MatrixXd(xy.topRows(half)) : Eigen::MatrixXd(xy.bottomRows(n - half)));
      }
    });
  }
  const Eigen::MatrixXd r = half > p + 1 ? triangular_factor(stacked) : triangular_factor(xy);
  // The rank decision as in fit_whitened: a column-pivoted QR of X's triangle.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(p, p);
  qr.setThreshold(tolerance);
  qr.compute(r.topLeftCorner(p, p));
  const Eigen::VectorXd z2 = qr.householderQ().adjoint() * r.col(p).head(p);
  return {r(p, p) * r(p, p) + z2.tail(p - qr.rank()).squaredNorm(), static_cast<int>(qr.rank())};
}

Eigen::MatrixXd new_directions(const Eigen::MatrixXd& c, const Eigen::MatrixXd& basis, double tolerance) {
  if (c.cols() == 0) return Eigen::MatrixXd(c.rows(), 0);
  const Eigen::RowVectorXd norms = c.colwise().norm();
  Eigen::MatrixXd r = c;
  if (basis.cols() > 0) {
    r -= basis * (basis.transpose() * r);
    r -= basis * (basis.transpose() * r);
  }
  // Keep columns with a meaningful part left, scaled by their original norm.
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < r.cols(); ++j) {
    if (norms(j) > 0 && r.col(j).norm() > tolerance * norms(j)) keep.push_back(j);
  }
  if (keep.empty()) return Eigen::MatrixXd(c.rows(), 0);
  Eigen::MatrixXd k(r.rows(), static_cast<Eigen::Index>(keep.size()));
  for (std::size_t i = 0; i < keep.size(); ++i) k.col(static_cast<Eigen::Index>(i)) = r.col(keep[i]) / norms(keep[i]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(k.rows(), k.cols());
  qr.setThreshold(tolerance);
  qr.compute(k);
  const Eigen::Index rank = qr.rank();
  return qr.householderQ() * Eigen::MatrixXd::Identity(k.rows(), rank);
}

}  // namespace gyrosid::explain
