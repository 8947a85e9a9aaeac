// `ipopt`: the joint problem of the `ceres` solver with bounds and constraints, by Ipopt's interior-point
// method (exact gradients; Gauss-Newton Hessian J'J, or limited-memory quasi-Newton):
//   min  1/2 sum_i r_i^2 + lambda/2 sum_j w_j^2
//   s.t. r_min <= r_jk <= r_max (as log-width bounds), centres within the data range plus a margin,
//        optionally sum_j w_j^2 <= bound (weight norm) or sum_j w_j^2 sum_k 1/r_jk^2 <= bound (roughness),
// with a fixed node budget: the network of the `init` solver cut at `nodes`.
// An iteration is one interior-point iteration; its cost is Ipopt's objective.
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct IpoptOptions {
  std::string init = "ols";
  OptionMap init_options;         // init.<key>=<value>
  int nodes = 80;                 // node budget (passed to the init solver as max_nodes)
  double min_width = 0.02, max_width = 3.0;
  std::string constraint = "none";  // none | weight_norm | roughness
  double bound = 0.0;             // the constraint's upper bound (0: 1.5 x its value at the start)
  double lambda = 1e-8;
  std::string hessian = "gauss_newton";  // gauss_newton | limited_memory
  double damping = 1e-2;
  int max_iterations = 200;
  double tolerance = 1e-9;
  int print_level = 0;            // Ipopt's own console output, 0 (silent) to 12
  OptionTable table();
  std::string validate() const;
};

class IpoptRbfSolver : public RbfSolverWithOptions<IpoptOptions> {
 public:
  explicit IpoptRbfSolver(Options options);
  std::string_view name() const override { return "ipopt"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

}  // namespace gyrosid
