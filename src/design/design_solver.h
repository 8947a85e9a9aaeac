// One interface for the optimisers of a calibration design, chosen by name from one registry (like the RBF
// solvers of solvers/solver.h) and compared on equal terms:
//
//   auto solver = make_design_solver("nlopt", {{"global_evaluations", "800"}}, seed);  // options validated
//   TableProfile best;
//   SolveSummary s = run_design_solver(*solver, problem, best);   // time, memory, objective history
//
//   nlopt  global derivative-free search over the box encoding, then a local derivative-free refinement
//   ipopt  interior point on the smooth relaxation with the chamber and budget limits as constraints,
//          finite-difference gradients, rounded to a programme at the end
//
// Each returns the programme with the lowest exact objective it evaluated; the summary's history holds the
// objective of every exact evaluation (nlopt) or of every interior-point iteration (ipopt, relaxed).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/checkpoint.h"
#include "core/registry.h"
#include "core/solve_summary.h"
#include "design/design_problem.h"
#include "solvers/common/options.h"

namespace gyrosid {
class Progress;
}

namespace gyrosid::design {

class DesignSolver {
 public:
  virtual ~DesignSolver() = default;
  virtual std::string_view name() const = 0;
  // Finds a programme in the problem's space; `best` arrives holding the space's initial programme.
  virtual SolveOutcome solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) = 0;
  // Finished stages (nlopt: the global search; ipopt: each start) are saved to, and on resume taken from,
  // this checkpoint (not owned; may be null). Every stage is deterministic given the seed, so a resumed
  // solve returns what an uninterrupted one would.
  void use_checkpoint(Checkpoint* checkpoint) { checkpoint_ = checkpoint; }

 protected:
  Checkpoint* checkpoint_ = nullptr;
};

SolveSummary run_design_solver(DesignSolver& solver, const DesignProblem& problem, TableProfile& best);

using DesignSolverRegistry = Registry<DesignSolver, const OptionMap&, std::uint64_t>;
const DesignSolverRegistry& design_solvers();
// The same registry, open for a program to add its own solvers before it makes any (not thread-safe:
// register at start-up). tests/design/toy_design_solver.cpp adds one this way.
DesignSolverRegistry& extend_design_solvers();
std::unique_ptr<DesignSolver> make_design_solver(const std::string& name, const OptionMap& options, std::uint64_t seed);

// --- the solvers -----------------------------------------------------------------------------------

struct NloptDesignOptions {
  std::string global = "GN_CRS2_LM";  // NLopt global derivative-free algorithm ("none": local only)
  int global_evaluations = 1200;
  int population = 0;                 // CRS2/ISRES/ESCH population (0: NLopt's default)
  std::string local = "LN_BOBYQA";    // local derivative-free refinement ("none": global only)
  int local_evaluations = 800;
  double xtol_rel = 1e-4;
  OptionTable table();
  std::string validate() const;
};

// Base of a design solver whose options struct O has defaults, table() and validate().
template <typename O>
class DesignSolverWithOptions : public WithOptions<DesignSolver, O> {
 public:
  DesignSolverWithOptions(O options, std::uint64_t seed) : WithOptions<DesignSolver, O>(std::move(options)), seed_(seed) {}

 protected:
  std::uint64_t seed_;
};

class NloptDesigner : public DesignSolverWithOptions<NloptDesignOptions> {
 public:
  using DesignSolverWithOptions::DesignSolverWithOptions;
  std::string_view name() const override { return "nlopt"; }
  SolveOutcome solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) override;
};

struct IpoptDesignOptions {
  int max_iterations = 60;
  double tolerance = 1e-4;          // Ipopt's convergence tolerance (relative)
  double gradient_step = 1e-4;      // forward-difference step on variables scaled to O(1)
  int starts = 1;                   // the initial programme, then seeded perturbations of it
  int print_level = 0;
  OptionTable table();
  std::string validate() const;
};

class IpoptDesigner : public DesignSolverWithOptions<IpoptDesignOptions> {
 public:
  using DesignSolverWithOptions::DesignSolverWithOptions;
  std::string_view name() const override { return "ipopt"; }
  SolveOutcome solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) override;

 private:
  struct StartResult {
    int status = 0;            // Ipopt's SolverReturn
    int iterations = 0;
    SmoothProgramme solution;  // empty when Ipopt returned no point
  };
  // One interior-point solve from the scaled point z, or its saved result under `key`.
  StartResult run_start(const DesignProblem& problem, SolveMonitor& monitor, Progress& progress, std::vector<double> z,
                        const std::string& key) const;
};

}  // namespace gyrosid::design
