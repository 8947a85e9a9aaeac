#include "solvers/nlopt/nlopt_solver.h"

#include <nlopt.h>

#include <cmath>

#include "core/bounded_search.h"
#include "core/error.h"
#include "solvers/ols/forward_selection.h"
#include "solvers/common/terminations.h"
#include "solvers/ols/ols_solver.h"

namespace gyrosid {

OptionTable NloptOptions::table() {
  OptionTable t("nlopt");
  t.text("algorithm", &algorithm, "NLopt algorithm name, derivative-free: LN_BOBYQA, LN_NELDERMEAD, GN_DIRECT_L, GN_CRS2_LM, ...")
      .choice("criterion", &criterion, {"loo", "gcv"}, "error of the inner OLS fit to minimise")
      .integer("evaluations", &evaluations, 2, 100000, "inner fits allowed")
      .real("width", &width, 0.0, 1e6, "starting width (normalised units)", true)
      .real("min_width", &min_width, 0.0, 1e6, "lower bound of the widths", true)
      .real("max_width", &max_width, 0.0, 1e6, "upper bound of the widths", true)
      .real("lambda", &lambda, 0.0, 1e6, "starting ridge parameter", true)
      .real("min_lambda", &min_lambda, 0.0, 1e6, "lower bound of lambda", true)
      .real("max_lambda", &max_lambda, 0.0, 1e6, "upper bound of lambda", true)
      .flag("per_input_widths", &per_input_widths, "one width per input (else one width for all)")
      .integer("candidates", &candidates, 0, 1000000, "candidate centres of the inner OLS")
      .integer("max_nodes", &max_nodes, 1, 100000, "node bound of the inner OLS")
      .integer("seed", &seed, 0, 1 << 30, "seed of NLopt's generator (global algorithms)");
  return t;
}

std::string NloptOptions::validate() const {
  const nlopt_algorithm a = nlopt_algorithm_from_string(algorithm.c_str());
  if (static_cast<int>(a) < 0 || a >= NLOPT_NUM_ALGORITHMS) {
    return str_cat("option 'algorithm' = '", algorithm, "' is not an NLopt algorithm (e.g. LN_BOBYQA, GN_DIRECT_L)");
  }
  if (algorithm.size() < 2 || algorithm[1] != 'N') {
    return str_cat("option 'algorithm' = '", algorithm, "' needs gradients; the inner selection has none - use an LN_* or GN_* algorithm");
  }
  if (!(min_width < max_width) || width < min_width || width > max_width) return "need min_width <= width <= max_width";
  if (!(min_lambda < max_lambda) || lambda < min_lambda || lambda > max_lambda) return "need min_lambda <= lambda <= max_lambda";
  return "";
}

SolveOutcome NloptRbfSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const NloptOptions& o = o_;
  const Eigen::Index d = problem.dimension();
  const Eigen::Index nw = o.per_input_widths ? d : 1;
  const unsigned nv = static_cast<unsigned>(nw + 1);

  ForwardSelectionOptions fs;
  fs.criterion = o.criterion == "loo" ? SelectionCriterion::loo : SelectionCriterion::gcv;
  fs.candidates = o.candidates;
  fs.max_nodes = o.max_nodes;
  fs.reestimate_lambda = false;
  auto configure = [&](const std::vector<double>& v) {
    fs.widths.resize(d);
    for (Eigen::Index k = 0; k < d; ++k) fs.widths(k) = std::exp(v[static_cast<std::size_t>(o.per_input_widths ? k : 0)]);
    fs.lambda = std::exp(v[static_cast<std::size_t>(nw)]);
  };
  const std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& v) {
    configure(v);
    double value = INFINITY;
    try {
      value = forward_select(problem.x, problem.y, fs).criterion;
    } catch (const Error&) {
      // e.g. widths so small that every candidate is collinear: an infeasible point, not a failure
    }
    monitor.iteration(value);
    return value;
  };
  std::vector<double> lb(nv), ub(nv), v(nv);
  for (Eigen::Index k = 0; k < nw; ++k) {
    lb[static_cast<std::size_t>(k)] = std::log(o.min_width);
    ub[static_cast<std::size_t>(k)] = std::log(o.max_width);
    v[static_cast<std::size_t>(k)] = std::log(o.width);
  }
  lb[static_cast<std::size_t>(nw)] = std::log(o.min_lambda);
  ub[static_cast<std::size_t>(nw)] = std::log(o.max_lambda);
  v[static_cast<std::size_t>(nw)] = std::log(o.lambda);
  BoundedSearchOptions search;
  search.algorithm = o.algorithm, search.max_evaluations = o.evaluations, search.xtol_rel = 1e-4;
  search.seed = static_cast<unsigned long>(o.seed);
  const BoundedSearchResult best = minimize_bounded(objective, v, lb, ub, search);
  if (!std::isfinite(best.value)) fail("nlopt: no hyper-parameter setting gave a valid fit");
  // NLopt's exceptions (round-off, forced stop) keep the best point seen: no progress, not a failure.
  const Termination termination = termination_of(best);

  configure(best.x);
  const ForwardSelectionResult r = forward_select(problem.x, problem.y, fs);
  fill_network(r, fs.widths, net);

  return {termination, best.message,
          {{"algorithm", o.algorithm}, {"criterion", o.criterion}, {"criterion_value", r.criterion},
           {"width", std::vector<double>(fs.widths.data(), fs.widths.data() + fs.widths.size())},
           {"lambda", fs.lambda}, {"candidates", r.candidates}}};
}

}  // namespace gyrosid
