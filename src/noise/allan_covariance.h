// The covariance of overlapping Allan-variance estimates at several averaging times, under a composite noise
// model (noise/composite.h) - the weight matrix of the noise identification (noise/identify.h) and the
// uncertainty of its parameters.
//
// With n samples at interval dt, phase points theta_0..theta_n, and at cluster size m (tau = m dt)
//   s_m = 1 / (2 tau^2 K_m) sum_{k<K_m} d_k^2,   d_k = theta_{k+2m} - 2 theta_{k+m} + theta_k,   K_m = n + 1 - 2m,
// two estimates covary, for Gaussian d, as
//   Cov(s_m, s_m') = 1 / (4 tau^2 tau'^2 K_m K_m') sum_j P(j) [2 c(j)^2 + 4 mu mu' c(j)]
// where c(j) = Cov(d_k, d'_{k+j}) = sum_ab g_a g'_b C(dt (j + b m' - a m)) with g = (1, -2, 1) and C the
// phase's generalised covariance, mu = R tau^2 the ramp's mean second difference, and P(j) the number of
// index pairs (k, k + j) in range. This is exact for Gaussian processes at every tau - no asymptotic edf
// and no independence between neighbouring taus is assumed. The sum over the lags j is taken exactly next
// to each kink of c and P (where one of the nine arguments or an index range crosses zero) and by graded
// Gauss-Legendre quadrature with Euler-Maclaurin end corrections in between, so its cost does not grow with
// n or m.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <span>

#include "noise/composite.h"

namespace gyrosid {

Eigen::MatrixXd allan_variance_covariance(const CompositeNoise& model, std::span<const std::size_t> cluster_sizes, std::size_t samples,
                                          double dt_s);

}  // namespace gyrosid
