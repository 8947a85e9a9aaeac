// Bounded minimisation by an NLopt algorithm - the shape of every inner search in gyrosid (RBF
// hyper-parameters, one node's centre and widths, a thermal-lag time constant): the objective is a
// std::function, and the best point ever evaluated is returned, also when NLopt stops on round-off or by an
// exception (its "ROUNDOFF_LIMITED" is not a failure of the search). Derivative-free algorithms (LN_*, GN_*)
// take the value alone; gradient-based ones (LD_*) an objective that also fills the gradient.
#pragma once

#include <nlopt.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/solve_summary.h"

namespace gyrosid {

struct BoundedSearchOptions {
  std::string algorithm = "LN_BOBYQA";  // an NLopt derivative-free algorithm (LN_* or GN_*)
  int max_evaluations = 100;
  double xtol_rel = 0.0, xtol_abs = 0.0;
  double initial_step = 0.0;             // the first trust radius (every coordinate); 0: NLopt's from the bounds
  std::optional<unsigned long> seed;     // NLopt's generator (global algorithms)
};

struct BoundedSearchResult {
  std::vector<double> x;                 // best point evaluated
  double value = INFINITY;
  int evaluations = 0;
  nlopt_result result = NLOPT_FAILURE;   // NLopt's own stopping code (when it returned normally)
  bool threw = false;                    // NLopt stopped by an exception (round-off, forced stop)
  std::string message;                   // NLopt's result name or the exception's text
};

// NLopt's stopping codes on the shared Termination: SUCCESS, STOPVAL, FTOL, XTOL -> converged; MAXEVAL ->
// evaluation_limit; MAXTIME -> iteration_limit; ROUNDOFF_LIMITED -> no_progress (the best point so far is
// kept); every failure code -> failed.
Termination termination_of(nlopt_result result);
// A search's termination: stopped by an exception (round-off, with its best point) reads no_progress.
Termination termination_of(const BoundedSearchResult& search);

BoundedSearchResult minimize_bounded(const std::function<double(const std::vector<double>&)>& objective, std::vector<double> start,
                                     const std::vector<double>& lower, const std::vector<double>& upper,
                                     const BoundedSearchOptions& options);

// value(x, gradient): the objective at x, filling `gradient` (same size as x) when it is not empty - NLopt
// asks for it only from gradient-based algorithms.
using ObjectiveWithGradient = std::function<double(const std::vector<double>& x, std::vector<double>& gradient)>;
BoundedSearchResult minimize_bounded(const ObjectiveWithGradient& objective, std::vector<double> start,
                                     const std::vector<double>& lower, const std::vector<double>& upper,
                                     const BoundedSearchOptions& options);

}  // namespace gyrosid
