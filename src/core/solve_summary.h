// The one summary every solve in gyrosid returns - RBF training, the classical and grey-box fits, the
// triad's joint solve, trajectory design - so experiments log and compare them on equal terms (as Ceres's
// Solver::Summary does for its problems).
//
//   SolveSummary s = timed_solve("nlopt", [&](SolveMonitor& m) {
//     ...  m.iteration(cost);  ...                       // once per iteration of the solver's outer loop
//     return SolveOutcome{Termination::converged, "xtol reached"};
//   });
//
// The wrapper records the wall time, the peak resident memory of the solve and the cost history, so no
// solver times itself. `iterations` is the number of entries of `cost_history`: one per iteration of the
// solver's outer loop (a selection step, a Levenberg-Marquardt step, an interior-point iteration, an
// objective evaluation of a derivative-free search - each solver's header says which). `evaluations`
// counts objective (or residual) evaluations where the solver distinguishes them.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"

namespace gyrosid {

enum class Termination {
  converged,         // a convergence test was met (tolerance, criterion minimum, KKT conditions)
  iteration_limit,   // stopped at the iteration cap: the result is the best so far, not certified
  evaluation_limit,  // stopped at the evaluation cap (derivative-free searches)
  no_progress,       // stopped because steps became too small to make progress (round-off, tiny step)
  failed,            // no usable result: numerical failure, infeasible, invalid problem
};

template <>
struct EnumNames<Termination> {
  static constexpr std::string_view kNoun = "termination";
  static constexpr std::array<std::pair<Termination, std::string_view>, 5> kTable{
      {{Termination::converged, "converged"},
       {Termination::iteration_limit, "iteration_limit"},
       {Termination::evaluation_limit, "evaluation_limit"},
       {Termination::no_progress, "no_progress"},
       {Termination::failed, "failed"}}};
};

// What a solve body reports; the wrapper adds the measured fields.
struct SolveOutcome {
  Termination termination = Termination::converged;
  std::string message;  // the back-end's own words (e.g. Ceres's message, NLopt's result name)
  nlohmann::json details = nlohmann::json::object();  // solver-specific figures, written as they are
};

struct SolveSummary {
  std::string solver;
  Termination termination = Termination::converged;
  std::string message;
  int iterations = 0;
  int evaluations = 0;
  std::vector<double> cost_history;
  double initial_cost = NAN, final_cost = NAN;  // first and last entry of the history, NaN without one
  double time_s = 0.0;
  double peak_rss_mb = 0.0;  // peak resident memory during the solve (process peak if the kernel cannot reset it)
  nlohmann::json details = nlohmann::json::object();

  // A result one may use: converged, or stopped at a limit or by lack of progress with its best point.
  bool usable() const { return termination != Termination::failed; }
};

// Given to every solve body: its iterations and evaluations are counted here, not by the solver.
class SolveMonitor {
 public:
  void iteration(double cost) { history_.push_back(cost); }
  void evaluation(int count = 1) { evaluations_ += count; }
  const std::vector<double>& history() const { return history_; }
  int evaluations() const { return evaluations_; }

 private:
  std::vector<double> history_;
  int evaluations_ = 0;
};

// Resets the kernel's resident-memory high-water mark of this process (Linux /proc/self/clear_refs), so a
// following peak_rss_mb() measures from now. Returns false where that is not possible.
bool reset_peak_rss();
// Peak resident memory of this process since start-up or since the last successful reset, MB.
double peak_rss_mb();

// Runs `body(SolveMonitor&) -> SolveOutcome` and returns its summary with time, memory and history.
template <typename Body>
SolveSummary timed_solve(std::string solver, Body&& body);

void to_json(nlohmann::json& j, const SolveSummary& s);
// A figure as JSON: the number, or null where it is NaN or infinite (JSON has neither).
nlohmann::json number_or_null(double v);
SolveSummary solve_summary_from_json(const nlohmann::json& j);

// --- implementation --------------------------------------------------------------------------------
namespace detail {
struct SolveClock {
  SolveClock();
  double seconds() const;
  bool memory_reset;
  double start_s;
};
SolveSummary finish_summary(std::string solver, const SolveClock& clock, SolveMonitor& monitor, SolveOutcome outcome);
}  // namespace detail

template <typename Body>
SolveSummary timed_solve(std::string solver, Body&& body) {
  const detail::SolveClock clock;
  SolveMonitor monitor;
  SolveOutcome outcome = body(monitor);
  return detail::finish_summary(std::move(solver), clock, monitor, std::move(outcome));
}

}  // namespace gyrosid
