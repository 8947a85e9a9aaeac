// Back-ends for a nonlinear least-squares problem (nls_problem.h), chosen by name from one registry and
// compared on equal terms - the triad's joint solve uses them, and so can trajectory design:
//
//   auto solver = make_nls_solver("nlopt", {{"algorithm", "LD_LBFGS"}});   // options validated here
//   SolveSummary s = solve(*solver, problem);       // the problem's blocks hold the solution
//
//   ceres   Levenberg-Marquardt on the residual blocks as they are (Ceres Solver, Jacobian scaling built in)
//   nlopt   a gradient-based NLopt algorithm on F(x) = 1/2 |r|^2 with gradient J'r (default LD_LBFGS)
//   ipopt   interior point (Ipopt) with the Gauss-Newton Hessian J'J, or L-BFGS
//
// nlopt and ipopt work in scaled variables u = D x with D the Jacobian's column norms at the start, and on
// F / F(start): the same conditioning Ceres gets from its Jacobi scaling, so all three see the same problem.
// Bounds of the parameter blocks are honoured by all three; fixed entries are never moved.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "core/registry.h"
#include "core/solve_summary.h"
#include "solvers/common/options.h"
#include "solvers/nls/nls_problem.h"

namespace gyrosid {

class NlsSolver {
 public:
  virtual ~NlsSolver() = default;
  virtual std::string_view name() const = 0;
  // Minimises from the problem's stored values and stores the solution there; one monitor iteration per
  // iteration of the back-end's outer loop (a Levenberg-Marquardt step, an NLopt evaluation, an Ipopt
  // iteration), its cost being F.
  virtual SolveOutcome minimize(NlsProblem& problem, SolveMonitor& monitor) = 0;
};

struct NlsCeresOptions {
  int max_iterations = 200;
  std::string linear_solver = "dense_qr";  // dense_qr | dense_normal_cholesky | sparse_normal_cholesky
  double function_tolerance = 1e-14;
  double gradient_tolerance = 1e-14;
  double parameter_tolerance = 1e-12;
  OptionTable table();
  std::string validate() const;
};

struct NlsNloptOptions {
  std::string algorithm = "LD_LBFGS";  // any gradient-based NLopt algorithm (LD_*)
  int max_evaluations = 5000;
  double ftol_rel = 1e-15;
  double xtol_rel = 1e-12;
  OptionTable table();
  std::string validate() const;
};

struct NlsIpoptOptions {
  std::string hessian = "gauss_newton";  // gauss_newton (J'J) | limited_memory
  int max_iterations = 200;
  double tolerance = 1e-12;
  int print_level = 0;
  OptionTable table();
  std::string validate() const;
};

// Base of a back-end whose options struct O has defaults, table() and validate() (what nls_entry needs).
template <typename O>
using NlsSolverWithOptions = WithOptions<NlsSolver, O>;

using NlsSolverRegistry = Registry<NlsSolver, const OptionMap&>;
const NlsSolverRegistry& nls_solvers();
std::unique_ptr<NlsSolver> make_nls_solver(const std::string& name, const OptionMap& options);

// Runs the back-end through timed_solve; details gain residuals, free parameters and the final cost.
SolveSummary solve(NlsSolver& solver, NlsProblem& problem);

}  // namespace gyrosid
