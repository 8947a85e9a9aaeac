// `lrols_loo`: locally regularised orthogonal least squares with the leave-one-out criterion (Chen, Hong,
// Harris & Sharkey 2004, "Sparse modelling using orthogonal forward regression with PRESS statistic and
// regularization", IEEE SMC-B 34(2)).
//
// Every orthogonal weight g_k has its own ridge parameter lambda_k. With candidates orthogonalised against
// the selected set (w_j), adding j updates the regularised residual and the LOO denominators recursively,
//   e_i <- e_i - w_ij g_j,   eta_i <- eta_i - w_ij^2 / (w_j'w_j + lambda_j),   g_j = w_j'y / (w_j'w_j + lambda_j),
// and the LOO mean square error J = mean((e_i / eta_i)^2) picks the candidate and stops the selection by
// itself when it no longer decreases. After each selection pass the lambda_k are updated by the evidence
// (Bayesian) rule lambda_k = gamma_k / (N - gamma) e'e / g_k^2, gamma_k = d_k/(d_k + lambda_k), and the
// selection is repeated until the set stops changing. O(N M) time per step, N x M memory.
// An iteration is one selection pass; its cost is the pass's leave-one-out mean square error.
#pragma once

#include "solvers/solver.h"

namespace gyrosid {

struct LrolsLooOptions {
  double width = 0.25;
  std::string widths;
  int candidates = 500;
  int max_nodes = 500;
  double lambda = 1e-6;   // initial lambda_k
  int passes = 4;         // selection + evidence-update passes
  OptionTable table();
  std::string validate() const;
};

class LrolsLooSolver : public RbfSolverWithOptions<LrolsLooOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "lrols_loo"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

}  // namespace gyrosid
