// `ceres`: every centre, log-width and weight of the network (plus a constant when asked) in one nonlinear
// least-squares problem, minimised by Levenberg-Marquardt in Ceres with analytic Jacobians:
//   min  sum_i r_i^2 + lambda sum_j w_j^2            (gaussian_sum_cost.h)
// started from another solver's network (`init`, default ols; its options passed as init.<key>=<value>).
// Linear algebra: dense QR, or SuiteSparse sparse Cholesky of the normal equations when Gaussians are
// truncated (exp(-z) taken as 0 beyond z = truncation, chunks of samples then touch only nearby nodes).
// Variable projection (Golub-Pereyra with Kaufman's Jacobian): the weights are solved linearly inside each
// evaluation and only centres and widths are iterated. Parameter covariance on request (ceres::Covariance).
// An iteration is one Levenberg-Marquardt step (Ceres's IterationSummary); its cost is Ceres's 1/2 |r|^2.
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct CeresOptions {
  std::string init = "ols";
  OptionMap init_options;      // init.<key>=<value>
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
  std::string validate() const;
};

class CeresRbfSolver : public RbfSolverWithOptions<CeresOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "ceres"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

// Trains `net` with the `init` solver and its own options (shared by ceres and ipopt); the init options are
// validated like any solver's. Returns the init solve's summary.
SolveSummary initial_network(const std::string& init, const OptionMap& init_options, const RbfProblem& problem,
                             RbfNetwork& net);
// Validates an init solver name and its options without solving (for validate()); "" when valid.
std::string check_init(const std::string& init, const OptionMap& init_options);

}  // namespace gyrosid
