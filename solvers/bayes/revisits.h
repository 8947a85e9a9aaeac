// Drift or misfit? (issue 11) A white fit's residual that is correlated in time is either noise that drifts
// (random walk, Gauss-Markov: a function of time) or the model's misfit (a function of the inputs, which a
// smooth trajectory also makes correlated in time - e.g. a noise-free recording). The evidence cannot tell
// them apart: both raise the likelihood of a coloured noise model. Revisits can: two samples at nearly the
// same inputs, far apart in time, share the misfit, but not the drift. Their half squared difference (the
// semivariogram) is, under the noise model,
//   gamma(lag) = white + gm_var (1 - exp(-lag / tau)) + rw_q lag / (2 dt),
// and near zero when the correlation is misfit. The ratio observed / predicted over such pairs is near 1
// for real drift and near 0 for misfit.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sensor/noise_model.h"

namespace gyrosid {

struct RevisitCheck {
  int pairs = 0;               // sample pairs at nearly the same inputs, at least `min_lag_s` apart
  double observed = 0.0;       // mean of (r_i - r_j)^2 / 2 over them
  double predicted = 0.0;      // mean of the noise model's gamma(lag) over them
  double min_lag_s = 0.0;
  double ratio() const { return predicted > 0 ? observed / predicted : 1.0; }
  std::string describe() const;
};

// Pairs: for up to 1000 query samples spread over the record, the sample nearest in inputs scaled by
// `widths` among those at least max(10 dt, tau) away in time, kept when within 0.1 width (Euclidean).
// O(1000 N d), no N x N matrix.
RevisitCheck check_revisits(const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths, const Eigen::VectorXd& r,
                            const std::vector<double>& t_s, const NoiseModel& model);

}  // namespace gyrosid
