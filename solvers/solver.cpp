#include "solvers/solver.h"

#include <cmath>

#include "core/error.h"
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
  return p;
}

nlohmann::json SolverSummary::to_json() const {
  return {{"solver", solver},   {"termination", termination}, {"iterations", iterations},
          {"cost_history", cost_history}, {"nodes", nodes}, {"time_s", time_s},
          {"peak_rss_mb", peak_rss_mb}, {"details", details}};
}

std::vector<std::string> solver_names() { return {"ols", "lrols_loo", "ofs_loo", "ceres", "nlopt", "ipopt"}; }

std::unique_ptr<RbfSolver> make_solver(const std::string& name, const OptionMap& options) {
  if (name == "ols") return std::make_unique<OlsSolver>(options);
  if (name == "lrols_loo") return std::make_unique<LrolsLooSolver>(options);
  if (name == "ofs_loo") return std::make_unique<OfsLooSolver>(options);
  if (name == "ceres") return std::make_unique<CeresRbfSolver>(options);
  if (name == "nlopt") return std::make_unique<NloptRbfSolver>(options);
  if (name == "ipopt") return std::make_unique<IpoptRbfSolver>(options);
  std::string known;
  for (const auto& n : solver_names()) known += (known.empty() ? "" : ", ") + n;
  fail("unknown solver '", name, "'; known: ", known);
}

std::string solver_help(const std::string& name) {
  if (name == "ols") return OlsSolver::help();
  if (name == "lrols_loo") return LrolsLooSolver::help();
  if (name == "ofs_loo") return OfsLooSolver::help();
  if (name == "ceres") return CeresRbfSolver::help();
  if (name == "nlopt") return NloptRbfSolver::help();
  if (name == "ipopt") return IpoptRbfSolver::help();
  fail("unknown solver '", name, "'");
}

}  // namespace gyrosid
