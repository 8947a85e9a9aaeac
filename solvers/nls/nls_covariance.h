// What the data determine in a least-squares problem (nls_problem.h), and how well.
//
// Observability: per residual group, the Jacobian over the group's free entries is column-scaled and
// factorised by Householder QR; walking the columns in priority order (the free entries' order: blocks
// added first come first), an entry is unobservable when its column lies in the span of the columns already
// accepted - its residual after projection (modified Gram-Schmidt on R, twice), the sine of its angle to
// that span, is below 1e-7 (exact collinearity: the entry can move without changing any residual). An entry
// that is not an anchor is also dropped when its sine to the span of the accepted anchors is below its own
// tolerance t: it would confound them (their sigmas inflated by about 1/t). Callers hold dropped entries at
// a nominal value and never report them as measured.
//
// Covariance at the solution: residuals of group g weighted by 1/s_g, s_g^2 = |r_g|^2 / (m_g - p_g) (the
// group's noise level, e.g. one gyro's), then ceres::Covariance (SuiteSparse QR; dense SVD when that
// fails): C = (J_w' J_w)^-1 over the free entries. `inflation` is sigma / sigma-if-every-other-entry-were-
// known, the factor by which correlation with the other entries widens an interval.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "solvers/nls/nls_problem.h"

namespace gyrosid {

struct NlsObservability {
  std::vector<bool> observable;     // per free entry
  std::vector<int> rank;            // per group: accepted columns
  std::vector<int> columns;         // per group: free entries the group touches
};

// `tolerance`, `anchor`: per free entry (empty: no anchor test).
NlsObservability analyse_observability(const NlsProblem& problem, const std::vector<double>& tolerance = {},
                                       const std::vector<bool>& anchor = {});

struct NlsCovariance {
  bool ok = false;
  std::string message;              // why not, when !ok
  std::vector<double> group_sigma;  // s_g, the residual standard deviation of each group
  std::vector<int> group_dof;       // m_g - p_g
  Eigen::MatrixXd covariance;       // free x free
  Eigen::VectorXd sigma;            // sqrt of its diagonal
  Eigen::VectorXd inflation;        // per free entry, >= 1
};

// At the problem's stored values (the solution). Needs every free entry observable (fix the others first).
NlsCovariance estimate_covariance(const NlsProblem& problem);

}  // namespace gyrosid
