// `gyrosid design` in the library: optimise a calibration programme for a time budget, or state the
// predicted accuracy of any trajectory.
//
//   auto envelope = std::make_shared<const Envelope>(load_envelope(settings.envelope, as_triad(sensor)));
//   const DesignSpace space = design_space(*envelope, settings.space);
//   DesignContext context(sensor, envelope, ModelFamily::rbf, settings.model, Criterion::cof, model_domain(space));
//   DesignResult r = design_trajectory(context, request);      // r.trajectory: an ordinary trajectory
//   Prediction p = evaluate_trajectory(context, spec);         // any trajectory, on its own samples
#pragma once

#include <cstdint>
#include <string>

#include "core/checkpoint.h"
#include "core/solve_summary.h"
#include "design/assessment.h"
#include "design/design_problem.h"
#include "design/design_space.h"
#include "design/design_solver.h"
#include "design/exact_selection.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid::design {

// Every option of a design besides the solver's, bound to key=value names (space.*, model.*, envelope.*,
// quadrature.*, select.*, prior.*) for `gyrosid design --set`.
struct DesignSettings {
  ModelOptions model;
  EnvelopeOptions envelope;
  DesignSpaceOptions space;
  QuadratureOptions quadrature;
  ExactSelectionOptions selection;
  PriorOptions prior;
  OptionTable table();  // binds this object's fields: keep it in place while the table is used
  static bool owns(const std::string& key);  // a key of this table (else: a solver option)
  // Applies the options that are this table's (space.*, model.*, ...); returns the others, the solver's.
  OptionMap apply(const OptionMap& options);
  // cof_minimax against a reference: the configuration measured against the dual scan on 10 seeds
  // (experiments/trajectory_design README, 2026-11-25 third session), each unless `given` (the --set options)
  // sets it: space.segments=10 (6 left the best worst-flight gain at 0.97-1.05x, 10 gave 1.26x), select.rounds=1
  // (a second round changed nothing), model.network_prior=evidence (hybrid).
  void minimax_defaults(const OptionMap& given);
};

struct DesignRequest {
  DesignSpaceOptions space;
  QuadratureOptions quadrature;
  ExactSelectionOptions selection;  // select.rounds > 0: the final choice by the exact predictor (exact_selection.h)
  PriorOptions prior;               // how a prior's members are combined (design_problem.h)
  std::string solver = "nlopt";
  OptionMap solver_options;
  std::uint64_t seed = 1;
  Checkpoint* checkpoint = nullptr;  // the solver's finished stages (design_solver.h); not owned, may be null
  // An adaptive session's segments already recorded (empty: none): the design continues them from their end
  // temperature, space.budget_min is the new part's, and it is judged, predicted and compared as recorded + new
  // (design_problem.h). The nlopt solver only.
  TableProfile recorded;
};

struct DesignResult {
  TrajectorySpec trajectory;   // kind programme, sampled at space.rate_hz (after recorded segments: the new part)
  Prediction predicted;        // on the trajectory's own samples (after recorded segments: on recorded + new)
  SolveSummary summary;        // with the exact selection: details["exact_selection"] (its candidates, choice, time)
  TableProfile initial;        // the programme the solver started from
  Prediction initial_predicted;
  // A design for a prior over sensors with more than one member: the design's prediction on each member (the
  // problem's order; `predicted` is the first's). Empty for one sensor.
  std::vector<Prediction> member_predictions;
};

// The chamber programme's space for a request: its temperatures around the envelope's.
DesignSpace design_space(const Envelope& envelope, const DesignSpaceOptions& options);
// The model's domain for designs in `space`: the programme's temperatures and the envelope's rates.
Domain model_domain(const DesignSpace& space);

DesignResult design_trajectory(const DesignContext& context, const DesignRequest& request);
// The design for a prior over sensors: the weighted mean of the members' objectives (design_problem.h). The
// exact selection (select.rounds > 0) compares against one reference and is refused for more than one member.
DesignResult design_trajectory(const std::vector<WeightedContext>& members, const DesignRequest& request);
// On the trajectory's own samples, with the model widened to the trajectory's temperatures when they exceed
// the context's domain (the model a user would fit to that trajectory).
Prediction evaluate_trajectory(const DesignContext& context, const TrajectorySpec& trajectory);
// Many predictions side by side (on up to worker_threads() threads, one Progress for all): each pair's is the
// same as evaluate_trajectory's alone. A prior's members are independent, and much of one prediction - the
// hybrid's evidence network along the trajectory - runs on one thread.
struct TrajectoryEvaluation {
  const DesignContext* context;
  const TrajectorySpec* trajectory;
};
std::vector<Prediction> evaluate_trajectories(const std::vector<TrajectoryEvaluation>& pairs);
// evaluate_trajectory's `objective` alone (the optimiser's, without the full prediction; seconds cheaper).
double trajectory_objective(const DesignContext& context, const TrajectorySpec& trajectory);
// The design's observations on the trajectory's own samples (for coverage plots and evaluation).
Observations observe_trajectory(const DesignContext& context, const TrajectorySpec& trajectory);

}  // namespace gyrosid::design
