// A final stage of a cof_minimax design that chooses by the exact predictor where it matters.
//
// The solvers optimise a proxy: the fixed dictionary's network (assessment.h), cheap enough to evaluate
// thousands of times. The prediction a design is judged by - and which matches the calibration's achieved
// criterion of fit (experiments/trajectory_design README, 2026-11-25) - takes the network the calibration
// would fit along the trajectory (model.network=evidence, evidence_network.h) and costs about 10 s of CPU.
// This stage spends a few of those on a small, diverse candidate set and returns the programme with the best
// EXACT worst-flight gain over the reference,
//
//   gain_f = R_f / cof_f,   R_f the reference's predicted criterion of fit on flight f, cof_f the candidate's,
//   score  = min_f gain_f   (target 2 of issue 9: beat the dual scan on every flight).
//
// Candidates: the solver's programme; then per round, from the incumbent (the best score so far),
//   corrected  the proxy re-solved from the incumbent with each flight's log ratio shifted by
//              c_f = x_f(exact) - x_f(proxy) at the incumbent (x_f the flight's log statistic ratio to the
//              reference, DesignContext::flight_log_ratios): the proxy made to agree with the exact predictor
//              where the search stands, a trust-region-like outer loop;
//   emphasis e the same with the incumbent's worst flight (exact) shifted by a further 2 log e: a programme
//              asked to win that flight e times more, traded against the others (the Pareto direction the
//              proxy's minimax alone does not take);
//   blends s   the incumbent compressed into 1 - s of the budget followed by the most emphasised programme
//              compressed into s (cycle periods kept, chamber ramps clipped to its rate limit).
// Each is scored by the exact predictor; the first candidate with the largest score wins (deterministic).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/assessment.h"
#include "design/design_problem.h"
#include "solvers/common/options.h"
#include "trajectory/table_profile.h"

namespace gyrosid::design {

struct ExactSelectionOptions {
  int rounds = 0;                       // 0: off (the solver's programme is the design, as before)
  // Defaults: one re-solve per round, the correction alone (the 2026-11-25 measurement: neither emphasis nor
  // blends won the worst flight on the reference sensor; experiments/trajectory_design README).
  std::string emphasis = "1";           // factors on the incumbent's worst flight per round (1: the correction alone)
  std::string blend_shares;             // budget shares of the most emphasised programme in blends ("": none), e.g. 0.3,0.5
  void bind(OptionTable& table);        // keys select.<name>
  std::string validate() const;
  // validate(), and select.rounds > 0 only for criterion cof_minimax with a reference.
  std::string validate(Criterion criterion, bool has_reference) const;
  std::vector<double> emphasis_factors() const;
  std::vector<double> shares() const;
};

struct SelectionCandidate {
  std::string name;
  TableProfile programme;
  Prediction predicted;          // the exact prediction
  std::vector<double> gain;      // R_f / cof_f per flight (envelope order)
  double worst_gain = 0.0;
  double proxy_objective = 0.0;  // the solver's objective (no offsets)
  std::vector<double> offsets;   // the proxy's per-flight offsets it was solved with (empty: none)
};

struct SelectionResult {
  std::vector<SelectionCandidate> candidates;
  std::vector<std::string> repeats;  // candidates that were a programme already scored (e.g. a re-solve that kept its start)
  std::size_t chosen = 0;
  nlohmann::json summary() const;  // per candidate: name, gains, worst gain, proxy objective, offsets; the choice
};

// R_f / cof_f per flight; fails when the prediction's flights are not the reference's.
std::vector<double> flight_gains(const Prediction& predicted, const std::vector<double>& reference_cof_m);
// The index of the largest min_f gains[i][f]; the first of equals.
std::size_t best_worst_flight(const std::vector<std::vector<double>>& gains);
// `first` compressed into (1 - share) of its own duration, then `second` into share of it; the chamber chained
// (each segment starts where the last ended, its ramp clipped to the chamber's rate limit), cycle periods kept.
TableProfile blend_programmes(const TableProfile& first, const TableProfile& second, double share);

// A solver run on `problem` (with its offsets) starting from `start`; returns the programme found.
using SolveFrom = std::function<TableProfile(const DesignProblem& problem, const TableProfile& start)>;
// The exact prediction of a programme (design.h's evaluate_trajectory on its samples).
using PredictExactly = std::function<Prediction(const TableProfile& programme)>;

// The stage above. `problem` is the solver's (cof_minimax, with a reference); `solved` the solver's programme.
SelectionResult select_by_exact(const DesignProblem& problem, const TableProfile& solved, const ExactSelectionOptions& options,
                                const SolveFrom& solve, const PredictExactly& predict);

}  // namespace gyrosid::design
