// What every Ceres solve in gyrosid shares: the cost of each iteration reported to the solve's monitor, and
// the covariance settings (dense SVD with a pseudo-inverse, so rank-deficient directions are reported
// rather than failing the whole computation).
#pragma once

#include <ceres/ceres.h>

#include "core/solve_summary.h"

namespace gyrosid {

// Reports every Levenberg-Marquardt iteration's cost to the monitor.
class MonitorCallback : public ceres::IterationCallback {
 public:
  explicit MonitorCallback(SolveMonitor& monitor) : monitor_(monitor) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    monitor_.iteration(s.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  SolveMonitor& monitor_;
};

// ceres::Covariance by dense SVD; directions with reciprocal condition below 1e-14 are dropped.
inline ceres::Covariance::Options dense_svd_covariance() {
  ceres::Covariance::Options o;
  o.algorithm_type = ceres::DENSE_SVD;
  o.null_space_rank = -1;
  o.min_reciprocal_condition_number = 1e-14;
  return o;
}

}  // namespace gyrosid
