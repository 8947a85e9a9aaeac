// `ofs_loo`: orthogonal forward selection of tunable nodes (Chen, Hong, Luk & Harris 2009, "Construction of
// tunable radial basis function networks using orthogonal forward selection", IEEE SMC-B 39(2)).
//
// Each stage adds one node whose centre and per-input widths are optimised to minimise the leave-one-out
// mean square error of the model given the nodes already chosen (the recursive LOO of lrols_loo). The
// paper searches with repeated weighted boosting; here a screening of candidate centres at a default width
// gives the start and NLopt's BOBYQA refines (centre, log widths) locally. Stages stop when the LOO error
// stops decreasing. Nodes are few and each has its own widths.
// An iteration is one node added (cost: the LOO error); evaluations count the BOBYQA objective calls.
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct OfsLooOptions {
  double width = 0.3;        // starting width of every stage (normalised units)
  double min_width = 0.02;   // bounds of the tuned widths
  double max_width = 3.0;
  int candidates = 300;      // screened starting centres
  int max_nodes = 200;
  int evaluations = 120;     // BOBYQA evaluations per node
  double lambda = 1e-8;      // ridge of every weight
  OptionTable table();
  std::string validate() const;
};

class OfsLooSolver : public RbfSolverWithOptions<OfsLooOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "ofs_loo"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

}  // namespace gyrosid
