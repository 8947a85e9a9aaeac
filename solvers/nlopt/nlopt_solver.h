// `nlopt`: the node width(s) and the ridge parameter as hyper-parameters, chosen by an NLopt algorithm to
// minimise the leave-one-out (or GCV) error of the OLS forward-selection fit inside - the thesis's "width by
// trial" (s5.6: "a training algorithm is required that optimises the spread"), automated.
// Variables: log r_k per input (or one log r), log lambda; bounded; derivative-free algorithms only (the
// inner selection is not differentiable in the widths). Global algorithms draw from NLopt's generator,
// seeded for determinism. An iteration is one inner fit (objective evaluation); its cost is the criterion.
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct NloptOptions {
  std::string algorithm = "LN_BOBYQA";
  std::string criterion = "loo";  // loo | gcv
  int evaluations = 40;
  double width = 0.25, min_width = 0.02, max_width = 2.0;
  double lambda = 1e-6, min_lambda = 1e-12, max_lambda = 1.0;
  bool per_input_widths = true;
  int candidates = 400;
  int max_nodes = 500;
  int seed = 1;
  OptionTable table();
  std::string validate() const;
};

class NloptRbfSolver : public RbfSolverWithOptions<NloptOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "nlopt"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

}  // namespace gyrosid
