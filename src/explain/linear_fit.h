// Least squares in the whitened space, by QR with column pivoting (never normal equations): the fit of a
// model's columns, the orthonormal basis of what they span, and the part of a candidate's columns that the
// model cannot absorb.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace gyrosid::explain {

struct WhitenedFit {
  Eigen::MatrixXd basis;     // orthonormal basis of the columns' span (N x rank)
  Eigen::VectorXd beta;      // coefficients, 0 for columns dropped as dependent
  Eigen::VectorXd residual;  // y - X beta
  double rss = 0.0;
  int rank = 0;
  std::vector<char> kept;    // per column: 1 when identifiable
};

// Columns whose pivoted-QR diagonal falls below tolerance * |R_11| are dropped as dependent.
WhitenedFit fit_whitened(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance = 1e-9);

// The residual sum of squares of fit_whitened(x, y) alone (same rank decision), without forming Q or the
// coefficients: for likelihoods evaluated many times.
double whitened_rss(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance = 1e-9);
// The same, with the rank fit_whitened would find.
struct RssAndRank {
  double rss = 0.0;
  int rank = 0;
};
RssAndRank whitened_rss_and_rank(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double tolerance = 1e-9);

// An orthonormal basis of the part of c orthogonal to `basis` (Gram-Schmidt twice, then pivoted QR);
// columns with less than `tolerance` of their norm left are dropped. Zero columns out: nothing new.
Eigen::MatrixXd new_directions(const Eigen::MatrixXd& c, const Eigen::MatrixXd& basis, double tolerance = 1e-6);

}  // namespace gyrosid::explain
