#include "solvers/solver.h"

#include <cmath>

#include "core/error.h"
#include "model/fit_notes.h"
#include "solvers/bayes/bayes_solver.h"
#include "solvers/ceres/ceres_solver.h"
#include "solvers/ipopt/ipopt_solver.h"
#include "solvers/lrols_loo/lrols_loo_solver.h"
#include "solvers/nlopt/nlopt_solver.h"
#include "solvers/ofs_loo/ofs_loo_solver.h"
#include "solvers/ols/ols_solver.h"

namespace gyrosid {

RbfNetwork RbfProblem::empty_network() const { return RbfNetwork(features, target, normalizer); }

void RbfProblem::unscale(RbfNetwork& net) const {
  net.weights *= y_scale;
  net.bias *= y_scale;
  if (net.weight_posterior) net.weight_posterior->scale(y_scale);
}

RbfProblem make_rbf_problem(const Dataset& data, NormalizationKind normalization) {
  if (!data.target.allFinite()) fail("rbf: the training recording has no reference rate (ref_rate_dps) to learn from");
  RbfProblem p;
  p.features = data.features;
  p.normalizer = Normalizer::make(normalization, data.features, data.x);
  p.x = p.normalizer.apply(data.x);
  const double rms = std::sqrt(data.target.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, data.size())));
  p.y_scale = rms > 0 ? rms : 1.0;
  p.y = data.target / p.y_scale;
  p.t_s = data.t_s;
  return p;
}

SolveSummary train(RbfSolver& solver, const RbfProblem& problem, RbfNetwork& net) {
  SolveSummary s = timed_solve(std::string(solver.name()), [&](SolveMonitor& monitor) { return solver.fit(problem, net, monitor); });
  FitNotes notes;
  notes.nodes = static_cast<int>(net.nodes());
  write_fit_notes(notes, s.details);
  return s;
}

const RbfSolverRegistry& rbf_solvers() { return extend_rbf_solvers(); }

RbfSolverRegistry& extend_rbf_solvers() {
  static RbfSolverRegistry registry = [] {
    RbfSolverRegistry r("solver");
    r.add(solver_entry<OlsSolver>("ols", "orthogonal least-squares forward selection (Chen 1991) with Orr's regularisation"))
        .add(solver_entry<LrolsLooSolver>("lrols_loo", "locally regularised OLS with leave-one-out selection (Chen et al. 2004)"))
        .add(solver_entry<OfsLooSolver>("ofs_loo", "orthogonal forward selection of tunable nodes by leave-one-out (Chen et al. 2009)"))
        .add(solver_entry<CeresRbfSolver>("ceres", "joint Levenberg-Marquardt over centres, log-widths and weights (Ceres Solver)"))
        .add(solver_entry<NloptRbfSolver>("nlopt", "widths and ridge tuned by NLopt on the LOO/GCV error of the inner OLS fit"))
        .add(solver_entry<IpoptRbfSolver>("ipopt", "bounded/constrained joint optimisation with a node budget (Ipopt)"))
        .add(solver_entry<BayesRbfSolver>("bayes", "Bayesian RBF: widths, prior and noise (white or coloured) by evidence maximisation; posterior covariance"));
    return r;
  }();
  return registry;
}

std::unique_ptr<RbfSolver> make_solver(const std::string& name, const OptionMap& options) { return rbf_solvers().make(name, options); }
std::vector<std::string> solver_names() { return rbf_solvers().names(); }
std::string solver_help(const std::string& name) { return rbf_solvers().at(name).help(); }

}  // namespace gyrosid
