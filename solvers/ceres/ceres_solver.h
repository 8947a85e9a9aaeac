// `ceres`: every centre, log-width and weight of the network (plus a constant when asked) in one nonlinear
// least-squares problem, minimised by Levenberg-Marquardt in Ceres with analytic Jacobians:
//   min  sum_i r_i^2 + lambda sum_j w_j^2            (gaussian_sum_cost.h)
// started from another solver's network (`init`, default ols; its options passed as init.<key>=<value>).
// Linear algebra: dense QR, or SuiteSparse sparse Cholesky of the normal equations when Gaussians are
// truncated (exp(-z) taken as 0 beyond z = truncation, chunks of samples then touch only nearby nodes).
// Variable projection (Golub-Pereyra with Kaufman's Jacobian): the weights are solved linearly inside each
// evaluation and only centres and widths are iterated. Parameter covariance on request (ceres::Covariance).
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct CeresOptions {
  std::string init = "ols";
  int max_iterations = 100;
  std::string linear_solver = "dense_qr";  // dense_qr | sparse_cholesky
  bool variable_projection = false;
  double lambda = 1e-8;        // ridge on the (scaled) weights
  bool covariance = false;
  double truncation = 30.0;    // sparse_cholesky: Gaussian taken as zero beyond exp(-truncation)
  bool bias = false;           // add a constant term
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  int chunk = 16;              // samples per residual block
  OptionTable table();
};

class CeresRbfSolver : public RbfSolver {
 public:
  explicit CeresRbfSolver(const OptionMap& options);
  std::string_view name() const override { return "ceres"; }
  SolverSummary train(const RbfProblem& problem, RbfNetwork& net) override;
  static std::string help();

 private:
  CeresOptions options_;
  OptionMap init_options_;
};

// Runs the `init` solver named in options, with its own options, on the problem (shared by ceres, ipopt).
SolverSummary initial_network(const std::string& init, const OptionMap& init_options, const RbfProblem& problem,
                              RbfNetwork& net);

}  // namespace gyrosid
