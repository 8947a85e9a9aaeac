// The `nlopt` design solver: a global derivative-free NLopt algorithm over the box encoding of the
// programme (every point feasible, design_space.h), then a local derivative-free refinement from the best
// point found. An iteration is one objective evaluation of an exact programme.
#include <nlopt.hpp>

#include <cmath>

#include "core/error.h"
#include "core/progress.h"
#include "design/design_solver.h"
#include "solvers/common/terminations.h"

namespace gyrosid::design {

OptionTable NloptDesignOptions::table() {
  OptionTable t("nlopt");
  t.text("global", &global, "NLopt global derivative-free algorithm (GN_CRS2_LM, GN_ISRES, GN_ESCH, GN_DIRECT_L, ...) or none")
      .integer("global_evaluations", &global_evaluations, 1, 1000000, "objective evaluations of the global search")
      .integer("population", &population, 0, 100000, "population of the global search (0: NLopt's default)")
      .text("local", &local, "NLopt local derivative-free algorithm (LN_BOBYQA, LN_SBPLX, LN_NELDERMEAD, ...) or none")
      .integer("local_evaluations", &local_evaluations, 1, 1000000, "objective evaluations of the local refinement")
      .real("xtol_rel", &xtol_rel, 0.0, 1.0, "relative step tolerance of both searches", true);
  return t;
}

namespace {

std::string check_algorithm(const std::string& key, const std::string& name, char scope) {
  if (name == "none") return "";
  const nlopt_algorithm a = nlopt_algorithm_from_string(name.c_str());
  if (static_cast<int>(a) < 0 || a >= NLOPT_NUM_ALGORITHMS) return str_cat("option '", key, "' = '", name, "' is not an NLopt algorithm");
  if (name.size() < 2 || name[0] != scope || name[1] != 'N') {
    return str_cat("option '", key, "' = '", name, "' must be a derivative-free ", scope == 'G' ? "global (GN_*)" : "local (LN_*)",
                   " algorithm");
  }
  return "";
}

// The objective over the design's box (design_space.h), counted, shown as progress and recorded: the best
// point any search has seen is kept, whatever the search returns.
class BoxSearch {
 public:
  BoxSearch(const DesignProblem& problem, const NloptDesignOptions& o, SolveMonitor& monitor, Progress& progress)
      : problem_(problem), o_(o), monitor_(monitor), progress_(progress) {}

  double operator()(const std::vector<double>& x) {
    const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    const double value = problem_.box_objective(v);
    monitor_.iteration(value);
    monitor_.evaluation();
    progress_.update(static_cast<std::size_t>(++evaluations));
    if (value < record.value) record = {value, v};
    return value;
  }

  // One NLopt search (a global GN_* or a local LN_* algorithm) from `start` over at most `allowed` evaluations;
  // `report` gets its algorithm, evaluations, best value and result.
  SolveOutcome run(const std::string& algorithm, int allowed, const Eigen::VectorXd& start, nlohmann::json& report) {
    const DesignSpace& space = problem_.space();
    const auto n = static_cast<unsigned>(space.box_dimension());
    const Eigen::VectorXd lower = space.box_lower(), upper = space.box_upper();
    nlopt::opt opt(algorithm.c_str(), n);
    opt.set_lower_bounds(std::vector<double>(lower.data(), lower.data() + n));
    opt.set_upper_bounds(std::vector<double>(upper.data(), upper.data() + n));
    opt.set_maxeval(allowed);
    opt.set_xtol_rel(o_.xtol_rel);
    if (o_.population > 0 && algorithm[0] == 'G') opt.set_population(static_cast<unsigned>(o_.population));
    if (algorithm[0] == 'L') {
      const Eigen::VectorXd step = 0.05 * (upper - lower);
      opt.set_initial_step(std::vector<double>(step.data(), step.data() + n));
    }
    opt.set_min_objective([](const std::vector<double>& x, std::vector<double>&, void* self) { return (*static_cast<BoxSearch*>(self))(x); }, this);
    std::vector<double> x(start.data(), start.data() + n);
    double value = 0.0;
    Termination termination = Termination::no_progress;
    std::string message;
    const int before = evaluations;
    try {
      const auto result = static_cast<nlopt_result>(opt.optimize(x, value));
      termination = termination_of(result);
      message = nlopt_result_to_string(result);
    } catch (const std::exception& e) {  // round-off and forced stops: the best point seen is kept
      message = std::string("stopped: ") + e.what();
    }
    report = {{"algorithm", algorithm}, {"evaluations", evaluations - before}, {"best", record.value}, {"result", message}};
    return SolveOutcome{termination, algorithm + ": " + message, {}};
  }

  struct {
    double value = INFINITY;
    Eigen::VectorXd v;
  } record;
  int evaluations = 0;

 private:
  const DesignProblem& problem_;
  const NloptDesignOptions& o_;
  SolveMonitor& monitor_;
  Progress& progress_;
};

}  // namespace

std::string NloptDesignOptions::validate() const {
  if (auto p = check_algorithm("global", global, 'G'); !p.empty()) return p;
  if (auto p = check_algorithm("local", local, 'L'); !p.empty()) return p;
  if (global == "none" && local == "none") return "options 'global' and 'local' cannot both be none";
  if (global == "GN_MLSL" || global == "GN_MLSL_LDS") return "option 'global': MLSL needs a local optimiser of its own; use GN_CRS2_LM, GN_ISRES, GN_ESCH or GN_DIRECT_L";
  return "";
}

SolveOutcome NloptDesigner::solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) {
  const DesignSpace& space = problem.space();
  const auto n = static_cast<unsigned>(space.box_dimension());
  const int total = (o_.global == "none" ? 0 : o_.global_evaluations) + (o_.local == "none" ? 0 : o_.local_evaluations);
  Progress progress("design (nlopt)", static_cast<std::size_t>(total));
  BoxSearch search(problem, o_, monitor, progress);
  auto& record = search.record;
  int& evaluations = search.evaluations;

  nlopt::srand(static_cast<unsigned long>(seed_));
  Eigen::VectorXd start = space.encode_box(best);
  nlohmann::json global_report, local_report;
  SolveOutcome outcome;
  // A finished global search is a checkpoint: a resumed design goes straight to the local refinement with the
  // same point, history and report (every evaluation is deterministic given the seed).
  const nlohmann::json& saved = checkpoint_ ? checkpoint_->record("nlopt/global") : nlohmann::json();
  if (o_.global != "none" && !saved.is_null()) {
    for (const double value : saved_numbers(saved.at("history"))) monitor.iteration(value), monitor.evaluation();
    evaluations = saved.at("evaluations").get<int>();
    const std::vector<double> v = saved.at("best_point");
    record = {saved.at("best_value").get<double>(), Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()))};
    global_report = saved.at("report");
    outcome = {parse_enum<Termination>(saved.at("termination").get<std::string>()), saved.at("message").get<std::string>(), {}};
    progress.update(static_cast<std::size_t>(evaluations));
  } else if (o_.global != "none") {
    const std::size_t first = monitor.history().size();
    outcome = search.run(o_.global, o_.global_evaluations, start, global_report);
    if (checkpoint_ && record.v.size() == n) {
      checkpoint_->save_record("nlopt/global", {{"history", std::vector<double>(monitor.history().begin() + static_cast<std::ptrdiff_t>(first), monitor.history().end())},
                                                {"evaluations", evaluations}, {"best_value", record.value},
                                                {"best_point", std::vector<double>(record.v.data(), record.v.data() + n)},
                                                {"report", global_report}, {"termination", to_string(outcome.termination)},
                                                {"message", outcome.message}});
    }
  }
  if (o_.local != "none") {
    if (record.v.size() == n) start = record.v;
    outcome = search.run(o_.local, o_.local_evaluations, start, local_report);
  }
  progress.finish();
  if (!std::isfinite(record.value)) fail("nlopt design: no programme had a finite objective");
  best = space.decode_box(record.v);
  outcome.details = {{"global", global_report}, {"local", local_report}, {"variables", n}};
  return outcome;
}

}  // namespace gyrosid::design
