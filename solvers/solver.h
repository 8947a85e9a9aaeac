// One interface for every RBF training back-end (solvers/<name>/), chosen by name from one registry and
// compared on equal terms:
//
//   auto solver = make_solver("ols", {{"criterion", "bic"}, {"width", "0.3"}});   // options validated here
//   RbfNetwork net = problem.empty_network();
//   SolveSummary s = train(*solver, problem, net);          // time, peak memory, cost history recorded
//
// A solver's options are a struct with defaults, an OptionTable binding their key=value names, and
// validate() for what the table's ranges cannot say (cross-field rules); make_solver checks both before any
// solve. Every solve returns the shared SolveSummary (core/solve_summary.h); its fit notes
// (model/fit_notes.h) give the size of the fitted network.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/registry.h"
#include "core/solve_summary.h"
#include "model/dataset.h"
#include "model/normalizer.h"
#include "model/rbf_network.h"
#include "solvers/common/options.h"

namespace gyrosid {

// The training problem in the network's own coordinates: normalised inputs, target scaled to unit RMS.
struct RbfProblem {
  std::vector<std::string> features;
  ModelTarget target = ModelTarget::error;
  Normalizer normalizer;
  Eigen::MatrixXd x;     // N x d, normalised
  Eigen::VectorXd y;     // N, target / y_scale
  double y_scale = 1.0;  // rad/s per unit of y
  std::vector<double> t_s;  // sample times (for solvers that model coloured noise); may be empty

  Eigen::Index size() const { return x.rows(); }
  Eigen::Index dimension() const { return x.cols(); }
  RbfNetwork empty_network() const;
  // Converts a network fitted to the scaled target (weights in y units) to rad/s, in place.
  void unscale(RbfNetwork& net) const;
};

RbfProblem make_rbf_problem(const Dataset& data, NormalizationKind normalization);

class RbfSolver {
 public:
  virtual ~RbfSolver() = default;
  virtual std::string_view name() const = 0;
  // Fits `net` (it arrives empty, with the problem's normaliser), reporting each iteration of the solver's
  // outer loop to the monitor.
  virtual SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) = 0;
};

// Base of a solver whose options struct O has defaults, table() and validate() (what solver_entry<S> needs).
template <typename O>
using RbfSolverWithOptions = WithOptions<RbfSolver, O>;

// Runs the solver through timed_solve; the summary's details gain "nodes".
SolveSummary train(RbfSolver& solver, const RbfProblem& problem, RbfNetwork& net);

using RbfSolverRegistry = Registry<RbfSolver, const OptionMap&>;
// Every RBF solver, in the order listings show them.
const RbfSolverRegistry& rbf_solvers();
// The same registry, open for a program to add its own solvers before it makes any (not thread-safe:
// register at start-up). tests/solvers/toy_rbf_solver.cpp adds one this way.
RbfSolverRegistry& extend_rbf_solvers();

std::unique_ptr<RbfSolver> make_solver(const std::string& name, const OptionMap& options);
std::vector<std::string> solver_names();
std::string solver_help(const std::string& name);  // the solver's options with defaults, ranges, meanings

// A registry entry for a solver class S with `using Options = ...;` (defaults, table(), validate()) and a
// constructor S(Options). Options are applied and validated when the solver is made.
template <typename S>
RbfSolverRegistry::Entry solver_entry(std::string name, std::string summary) {
  return options_entry<RbfSolver, S>(std::move(name), std::move(summary), "");
}

}  // namespace gyrosid
