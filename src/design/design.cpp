#include "design/design.h"

#include <atomic>
#include <chrono>

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"

namespace gyrosid::design {

OptionTable DesignSettings::table() {
  OptionTable t("design");
  space.bind(t);
  model.bind(t);
  envelope.bind(t);
  quadrature.bind(t);
  selection.bind(t);
  prior.bind(t);
  return t;
}

bool DesignSettings::owns(const std::string& key) {
  for (const char* prefix : {"space.", "model.", "envelope.", "quadrature.", "select.", "prior."}) {
    if (key.rfind(prefix, 0) == 0) return true;
  }
  return false;
}

OptionMap DesignSettings::apply(const OptionMap& options) {
  OptionMap own, others;
  for (const auto& [key, value] : options) (owns(key) ? own : others)[key] = value;
  table().apply(own);
  return others;
}

void DesignSettings::minimax_defaults(const OptionMap& given) {
  if (!given.count("space.segments")) space.segments = 10;
  if (!given.count("select.rounds")) selection.rounds = 1;
  if (!given.count("model.network_prior")) model.network_prior = "evidence";
}

Observations observe_trajectory(const DesignContext& context, const TrajectorySpec& t) {
  const std::vector<double> times = t.times();
  const Quadrature q = sample_quadrature(times, t.profile.duration_s());
  return observe(t.profile, q.times, q.weights_s, context.gyro(), context.thermal());
}

DesignSpace design_space(const Envelope& envelope, const DesignSpaceOptions& options) {
  return DesignSpace(options, envelope.domain.temp_min_c, envelope.domain.temp_max_c, envelope.domain.rate_max_radps);
}

Domain model_domain(const DesignSpace& space) {
  Domain d;
  d.temp_min_c = space.temp_lo();
  d.temp_max_c = space.temp_hi();
  d.rate_max_radps = space.rate_max_radps();
  return d;
}

namespace {

// The context widened to the trajectory's temperatures and rates when they exceed its domain (null: no need).
std::unique_ptr<DesignContext> widened(const DesignContext& context, const Observations& o) {
  Domain d = context.model_domain();
  const double lo = o.inputs.temp_c.minCoeff(), hi = o.inputs.temp_c.maxCoeff();
  const double w = o.inputs.rate.cwiseAbs().maxCoeff();
  if (lo >= d.temp_min_c && hi <= d.temp_max_c && w <= d.rate_max_radps * 1.05) return nullptr;
  d.temp_min_c = std::min(d.temp_min_c, lo), d.temp_max_c = std::max(d.temp_max_c, hi);
  d.rate_max_radps = std::max(d.rate_max_radps, w);
  return context.with_domain(d);
}

}  // namespace

Prediction evaluate_trajectory(const DesignContext& context, const TrajectorySpec& t) {
  const Observations o = observe_trajectory(context, t);
  const std::unique_ptr<DesignContext> wide = widened(context, o);
  const DesignContext& c = wide ? *wide : context;
  // The hybrid's network as the calibration would fit it along this trajectory (model.network=evidence).
  // Its `objective` stays the optimiser's (the fixed dictionary's), so that designs and their reports compare.
  if (const auto followed = c.following(o)) {
    Prediction p = followed->predict(o);
    p.objective = c.objective(c.estimate(o, c.objective_needs_target()));
    return p;
  }
  return c.predict(o);
}

std::vector<Prediction> evaluate_trajectories(const std::vector<TrajectoryEvaluation>& pairs) {
  std::vector<Prediction> out(pairs.size());
  Progress progress(str_cat("design: predicting ", pairs.size(), " trajectory-sensor pairs"), pairs.size());
  std::atomic<std::size_t> done = 0;
  parallel_for(static_cast<std::ptrdiff_t>(pairs.size()), [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (std::ptrdiff_t k = begin; k < end; ++k) {
      {
        const ProgressSilenced quiet;
        out[static_cast<std::size_t>(k)] = evaluate_trajectory(*pairs[static_cast<std::size_t>(k)].context, *pairs[static_cast<std::size_t>(k)].trajectory);
      }
      ++done;
      if (begin == 0) progress.update(done);  // one thread reports for all
    }
  });
  return out;
}

double trajectory_objective(const DesignContext& context, const TrajectorySpec& t) {
  const Observations o = observe_trajectory(context, t);
  const std::unique_ptr<DesignContext> wide = widened(context, o);
  const DesignContext& c = wide ? *wide : context;
  return c.objective(c.estimate(o, c.objective_needs_target()));
}

DesignResult design_trajectory(const DesignContext& context, const DesignRequest& request) {
  return design_trajectory(std::vector<WeightedContext>{{&context, 1.0}}, request);
}

DesignResult design_trajectory(const std::vector<WeightedContext>& members, const DesignRequest& request) {
  if (members.empty()) fail("design: a prior over sensors needs at least one member");
  const DesignContext& context = *members.front().context;
  if (auto p = request.selection.validate(context.criterion(), !context.reference_cof_m().empty()); !p.empty()) fail("design: ", p);
  if (members.size() > 1 && request.selection.rounds > 0) {
    fail("design: the exact selection (select.rounds > 0, cof_minimax's default) is not available under a prior of ",
         members.size(), " sensors; set select.rounds=0");
  }
  const bool continuing = !request.recorded.segments.empty();
  if (continuing && (request.solver != "nlopt" || request.selection.rounds > 0)) {
    fail("design: continuing recorded segments takes the nlopt solver without the exact selection (select.rounds=0), not ", request.solver);
  }
  auto solver = make_design_solver(request.solver, request.solver_options, request.seed);
  solver->use_checkpoint(request.checkpoint);
  DesignSpaceOptions space_options = request.space;
  if (continuing) space_options.start_c = request.recorded.segments.back().chamber_end_c;
  const DesignSpace space = design_space(context.envelope(), space_options);
  DesignProblem problem(members, space, request.quadrature, request.prior);
  problem.set_recorded(request.recorded);
  DesignResult r;
  r.initial = space.initial();
  if (continuing) problem.continued(r.initial);  // a recording that cannot be continued fails here, by name
  TableProfile best = r.initial;
  r.summary = run_design_solver(*solver, problem, best);
  if (!r.summary.usable()) fail("design: the ", request.solver, " solver failed: ", r.summary.message);
  auto spec = [&](TableProfile p) {
    TrajectorySpec t;
    t.profile = std::move(p);
    t.sampling.rate_hz = request.space.rate_hz;
    return t;
  };
  std::optional<Prediction> chosen;
  if (request.selection.rounds > 0) {
    const auto start = std::chrono::steady_clock::now();
    // Re-solves start from the incumbent (no checkpoint: its saved stages belong to the first solve).
    const SolveFrom solve = [&](const DesignProblem& shifted, const TableProfile& from) {
      auto again = make_design_solver(request.solver, request.solver_options, request.seed);
      TableProfile found = from;
      const SolveSummary s = run_design_solver(*again, shifted, found);
      if (!s.usable()) fail("design: the ", request.solver, " solver failed in the exact selection: ", s.message);
      return found;
    };
    const PredictExactly predict = [&](const TableProfile& p) { return evaluate_trajectory(context, spec(p)); };
    const SelectionResult selection = select_by_exact(problem, best, request.selection, solve, predict);
    best = selection.candidates[selection.chosen].programme;
    chosen = selection.candidates[selection.chosen].predicted;
    nlohmann::json summary = selection.summary();
    summary["rounds"] = request.selection.rounds;
    summary["emphasis"] = request.selection.emphasis;
    summary["blend_shares"] = request.selection.blend_shares;
    summary["time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.summary.details["exact_selection"] = summary;
    r.summary.details["objective"] = problem.objective(best);  // the chosen programme's proxy objective
  }
  r.trajectory = spec(best);
  r.trajectory.description = str_cat("designed by gyrosid design (", to_string(context.family()), " model, criterion ",
                                     to_string(context.criterion()), ", solver ", request.solver,
                                     request.selection.rounds > 0 ? ", chosen by the exact predictor" : "", ", seed ", request.seed, ")");
  const TrajectorySpec judged = spec(problem.continued(best));  // recorded + new
  // The design (unless the exact selection predicted it), the initial trajectory, and the design on every
  // further member of the prior, side by side.
  const TrajectorySpec initial = spec(problem.continued(r.initial));
  std::vector<TrajectoryEvaluation> pairs{{&context, &initial}};
  if (!chosen) pairs.push_back({&context, &judged});
  for (std::size_t k = 1; k < members.size(); ++k) pairs.push_back({members[k].context, &judged});
  const std::vector<Prediction> p = evaluate_trajectories(pairs);
  r.initial_predicted = p[0];
  r.predicted = chosen ? *chosen : p[1];
  if (members.size() > 1) {
    r.member_predictions.push_back(r.predicted);
    r.member_predictions.insert(r.member_predictions.end(), p.end() - static_cast<std::ptrdiff_t>(members.size() - 1), p.end());
  }
  return r;
}

}  // namespace gyrosid::design
