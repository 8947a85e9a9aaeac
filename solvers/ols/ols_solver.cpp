#include "solvers/ols/ols_solver.h"

#include "core/error.h"
#include "model/fit_notes.h"
#include "solvers/common/candidates.h"

namespace gyrosid {

OptionTable OlsOptions::table() {
  OptionTable t("ols");
  t.choice("criterion", &criterion, {"bic", "gcv", "uev", "fpe", "loo"}, "stopping criterion (thesis: bic)")
      .real("width", &width, 0.0, 1e6, "node width r in normalised input units (every input)", true)
      .text("widths", &widths, "per-input widths, comma-separated (overrides width)")
      .integer("candidates", &candidates, 0, 1000000, "candidate centres: a space-filling subset of the training points (0 = all)")
      .integer("max_nodes", &max_nodes, 1, 100000, "upper bound on the number of nodes")
      .real("lambda", &lambda, 0.0, 1e6, "initial global ridge parameter (unit-RMS target)")
      .flag("reestimate_lambda", &reestimate_lambda, "re-estimate lambda by GCV after every step (Orr)")
      .integer("patience", &patience, 1, 1000, "steps without improvement of the criterion before stopping")
      .real("collinear_tolerance", &collinear_tolerance, 1e-15, 1e-2,
            "skip a candidate once its squared norm left after orthogonalisation is below this fraction");
  return t;
}

std::string OlsOptions::validate() const { return check_positive_list(widths, "widths"); }

ForwardSelectionOptions OlsOptions::selection(Eigen::Index dimension) const {
  ForwardSelectionOptions s;
  s.criterion = parse_enum<SelectionCriterion>(criterion);
  s.widths = node_widths(width, parse_list(widths, "ols option 'widths'"), dimension);
  s.candidates = candidates;
  s.max_nodes = max_nodes;
  s.lambda = lambda;
  s.reestimate_lambda = reestimate_lambda;
  s.patience = patience;
  s.collinear_tolerance = collinear_tolerance;
  return s;
}

void fill_network(const ForwardSelectionResult& r, const Eigen::RowVectorXd& widths, RbfNetwork& net) {
  net.centres = r.centres;
  net.widths = widths.replicate(r.centres.rows(), 1);
  net.weights = r.weights;
  net.bias = 0.0;
}

SolveOutcome OlsSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const ForwardSelectionOptions s = o_.selection(problem.dimension());
  const ForwardSelectionResult r = forward_select(problem.x, problem.y, s);
  for (double c : r.criterion_history) monitor.iteration(c);
  fill_network(r, s.widths, net);
  SolveOutcome outcome{r.termination, r.stop_reason,
                       {{"criterion", o_.criterion}, {"criterion_value", r.criterion},
                        {"effective_parameters", r.effective_parameters}, {"rss", r.rss}, {"candidates", r.candidates},
                        {"skipped_collinear", r.skipped_collinear},
                        {"width", std::vector<double>(s.widths.data(), s.widths.data() + s.widths.size())}}};
  FitNotes notes;
  notes.ridge_lambda = r.lambda;
  write_fit_notes(notes, outcome.details);
  return outcome;
}

}  // namespace gyrosid
