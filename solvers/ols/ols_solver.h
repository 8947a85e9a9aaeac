// `ols`: forward selection by error-reduction ratio with Orr's global ridge regression (forward_selection.h).
// Fixed node width(s) chosen by the user - the thesis's method (Orr's toolbox, BIC, width by trial).
// An iteration is one selection step (one node added); the cost history is the selection criterion.
#pragma once

#include "solvers/ols/forward_selection.h"
#include "solvers/solver.h"

namespace gyrosid {

struct OlsOptions {
  std::string criterion = "bic";
  double width = 0.25;          // normalised input units, every input
  std::string widths;           // optional per-input widths "0.2,0.4"
  int candidates = 1000;
  int max_nodes = 500;
  double lambda = 1e-6;
  bool reestimate_lambda = true;
  int patience = 3;
  double collinear_tolerance = 1e-9;
  OptionTable table();
  std::string validate() const;
  ForwardSelectionOptions selection(Eigen::Index dimension) const;
};

class OlsSolver : public RbfSolverWithOptions<OlsOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "ols"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

// Copies a forward-selection result into a network (weights still in target units).
void fill_network(const ForwardSelectionResult& r, const Eigen::RowVectorXd& widths, RbfNetwork& net);

}  // namespace gyrosid
