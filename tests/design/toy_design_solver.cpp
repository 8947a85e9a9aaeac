// A toy design solver added from the test binary alone, proving the extension point of
// design/design_solver.h: a solver is an options struct, a class and one registration line; the property
// suite of test_design_solver_properties.cpp then runs over it like over nlopt and ipopt.
//
// compass: coordinate (compass) search over the box encoding (design_space.h). Each sweep tries every
// coordinate +- step x its range, keeps the first improvement, and halves the step after a sweep without one.
#include <algorithm>
#include <string>

#include "core/format.h"
#include "design/design_solver.h"

namespace gyrosid::design {
namespace {

struct CompassOptions {
  int evaluations = 120;
  double step = 0.25;  // first step, a share of each coordinate's range
  OptionTable table() {
    OptionTable t("compass");
    t.integer("evaluations", &evaluations, 1, 1000000, "objective evaluations")
        .real("step", &step, 0.0, 1.0, "first step, share of each coordinate's range", true);
    return t;
  }
  std::string validate() const { return ""; }
};

class CompassDesigner : public DesignSolverWithOptions<CompassOptions> {
 public:
  using DesignSolverWithOptions::DesignSolverWithOptions;
  std::string_view name() const override { return "compass"; }
  SolveOutcome solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) override {
    const DesignSpace& space = problem.space();
    const Eigen::VectorXd lo = space.box_lower(), hi = space.box_upper();
    Eigen::VectorXd v = space.encode_box(best);
    double value = problem.box_objective(v), step = o_.step;
    monitor.evaluation();
    monitor.iteration(value);
    while (monitor.evaluations() < o_.evaluations && step > 1e-4) {
      bool improved = false;
      for (Eigen::Index i = 0; i < v.size() && monitor.evaluations() < o_.evaluations; ++i) {
        for (double sign : {1.0, -1.0}) {
          Eigen::VectorXd trial = v;
          trial(i) = std::clamp(v(i) + sign * step * (hi(i) - lo(i)), lo(i), hi(i));
          const double f = problem.box_objective(trial);
          monitor.evaluation();
          if (f < value) {
            v = trial, value = f, improved = true;
            break;
          }
        }
      }
      monitor.iteration(value);
      if (!improved) step *= 0.5;
    }
    best = space.decode_box(v);
    return {monitor.evaluations() >= o_.evaluations ? Termination::evaluation_limit : Termination::converged,
            str_cat("compass search, final step ", step), {}};
  }
};

// The one registration line, run before gtest lists or instantiates the tests.
const bool registered = [] {
  extend_design_solvers().add(options_entry<DesignSolver, CompassDesigner, std::uint64_t>(
      "compass", "toy: coordinate search over the box encoding", "design solver "));
  return true;
}();

}  // namespace
}  // namespace gyrosid::design
