// Drift or misfit? (issue 11) A white fit's residual that is correlated in time is either noise that drifts
// (random walk, Gauss-Markov: a function of time) or the model's misfit (a function of the inputs, which a
// smooth trajectory also makes correlated in time - e.g. a noise-free recording). The evidence cannot tell
// them apart: both raise the likelihood of a coloured noise model. Revisits can: two samples at nearly the
// same inputs, far apart in time, share the misfit but not the drift. Their half squared residual difference
// is compared with the residual's semivariance at the same lag along the record (all pairs that far apart,
// whatever their inputs: drift plus the misfit's change):
//   ratio = mean (r_i - r_j)^2 / 2 over revisits  /  mean gamma(lag_ij),  gamma(k) = mean_m (r_m - r_{m+k})^2 / 2,
// near 1 when the correlation is drift, near 0 when it is misfit. Model-free: a noise model that lets a random
// walk stand in for a Gauss-Markov term would overstate the drift at long lags.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "noise/state_space.h"

namespace gyrosid {

struct RevisitCheck {
  int pairs = 0;               // sample pairs at nearly the same inputs, at least `min_lag_s` apart
  double observed = 0.0;       // mean of (r_i - r_j)^2 / 2 over them
  double predicted = 0.0;      // mean of the residual's semivariance at their lags along the record
  double min_lag_s = 0.0;
  double ratio() const { return predicted > 0 ? observed / predicted : 1.0; }
  std::string describe() const;
};

// Pairs: for up to 1000 query samples spread over the record, the sample nearest in inputs scaled by
// `widths` among those at least max(10 dt, tau of `model`) away in time, kept when within 0.1 width
// (Euclidean); lags in samples (regular sampling). O(1000 N d), no N x N matrix.
RevisitCheck check_revisits(const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths, const Eigen::VectorXd& r,
                            const std::vector<double>& t_s, const NoiseModel& model);

}  // namespace gyrosid
