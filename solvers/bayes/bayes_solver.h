// `bayes`: the Gaussian RBF network as a Bayesian linear model whose hyper-parameters are set by type-II
// maximum likelihood (bayes_fit.h, evidence.h) - per-input widths, the prior precision of the weights and the
// noise precision (or a coloured noise model, Kalman-whitened) - with the posterior covariance of the weights
// kept in the network (predict_with_sigma). Centres: a farthest-point dictionary of the training inputs; the
// constant has a flat prior. An iteration is one evidence evaluation; its cost is -log evidence per sample.
#pragma once

#include "solvers/bayes/bayes_fit.h"
#include "solvers/solver.h"

namespace gyrosid {

struct BayesOptions : BayesFitOptions {
  OptionTable table();
};

class BayesRbfSolver : public RbfSolverWithOptions<BayesOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "bayes"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override;
};

}  // namespace gyrosid
