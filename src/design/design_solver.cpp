#include "design/design_solver.h"

namespace gyrosid::design {

SolveSummary run_design_solver(DesignSolver& solver, const DesignProblem& problem, TableProfile& best) {
  SolveSummary s = timed_solve(std::string(solver.name()), [&](SolveMonitor& monitor) { return solver.solve(problem, best, monitor); });
  s.details["objective"] = problem.objective(best);
  return s;
}

const DesignSolverRegistry& design_solvers() { return extend_design_solvers(); }

DesignSolverRegistry& extend_design_solvers() {
  static DesignSolverRegistry registry = [] {
    DesignSolverRegistry r("design solver");
    r.add(options_entry<DesignSolver, NloptDesigner, std::uint64_t>(
             "nlopt", "NLopt: global derivative-free search of the programme, then local refinement", "design solver "))
        .add(options_entry<DesignSolver, IpoptDesigner, std::uint64_t>(
            "ipopt", "Ipopt: interior point on the smooth relaxation, limits as constraints", "design solver "));
    return r;
  }();
  return registry;
}

std::unique_ptr<DesignSolver> make_design_solver(const std::string& name, const OptionMap& options, std::uint64_t seed) {
  return design_solvers().make(name, options, seed);
}

}  // namespace gyrosid::design
