// What the nlopt and ipopt back-ends of nls_solver.h minimise: F(x) / F(x0) over scaled variables
// u = D x, D = the Jacobian's column norms at the start x0 (1 for a zero column) - the conditioning Ceres
// gets from its Jacobi scaling. Keeps the best point evaluated, so a back-end stopping on round-off never
// returns a worse one; and ceres_problem() hands an NlsProblem to Ceres (solve and covariance).
#pragma once

#include <ceres/problem.h>

#include <Eigen/Core>

#include "core/solve_summary.h"
#include "solvers/nls/nls_problem.h"

namespace gyrosid {

class ScaledObjective {
 public:
  // `report_every_evaluation`: each evaluation is an iteration of the monitor (NLopt); else the back-end
  // reports its iterations through report() (Ipopt).
  ScaledObjective(NlsProblem& problem, SolveMonitor& monitor, bool report_every_evaluation = true);

  Eigen::Index size() const { return scale_.size(); }
  const Eigen::VectorXd& start() const { return start_; }
  Eigen::VectorXd scaled_lower() const;
  Eigen::VectorXd scaled_upper() const;

  // F(u / D) / F0, with its gradient and Gauss-Newton matrix in u when asked (cached for the last u).
  double value(const Eigen::VectorXd& u, Eigen::VectorXd* gradient, Eigen::MatrixXd* gauss_newton);
  void report(double scaled_value) { monitor_.iteration(scaled_value * cost0_); }
  // Writes the best point evaluated into the problem.
  void store_best();

 private:
  NlsProblem& problem_;
  SolveMonitor& monitor_;
  bool report_every_;
  Eigen::VectorXd scale_, start_;
  double cost0_ = 1.0;
  Eigen::VectorXd best_u_;
  double best_ = INFINITY;
  // cache of the last derivative evaluation
  Eigen::VectorXd cached_u_, cached_gradient_;
  Eigen::MatrixXd cached_gn_;
  double cached_value_ = 0.0;
};

ceres::Problem ceres_problem(NlsProblem& problem);

}  // namespace gyrosid
