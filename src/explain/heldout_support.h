// Held-out samples outside the training blocks' support: where the simulation's prediction is an
// extrapolation. A flexible baseline (a spline surface over (T, omega)) fitted on the training blocks is
// undetermined at (T, omega) pairs they did not visit; its error on held-out samples there belongs to the
// baseline, not to missing physics, and no effect can remove it. Such samples neither confirm effects nor
// count in the held-out fit or the residual diagnostics; explain reports how many there were.
//
// The measure is a held-out sample's leverage under the ordinary least-squares fit of the model's columns
// on the training rows, h = x' (X'X)^+ x (Cook & Weisberg 1982, Residuals and Influence in Regression,
// s2.1): its prediction variance in units of the noise variance. Over the training rows h averages p/n (p
// the rank); a held-out sample above `ratio` times that mean is outside the support. Directions the
// training rows do not determine (singular values below 1e-6 of the largest, columns scaled to unit norm)
// count at that floor: a held-out sample with any component along them is outside the support.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace gyrosid::explain {

// `x`: the model's columns on every sample; `heldout`: 1 for held-out samples. Returns 1 for the held-out
// samples outside the training rows' support (0 for every training sample).
std::vector<char> outside_training_support(const Eigen::MatrixXd& x, const std::vector<char>& heldout, double ratio);

}  // namespace gyrosid::explain
