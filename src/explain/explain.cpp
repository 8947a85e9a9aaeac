#include "explain/explain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "core/axis_view.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "explain/heldout_support.h"
#include "explain/judge.h"
#include "explain/noise_likelihood.h"
#include "explain/refit.h"
#include "explain/simulation.h"
#include "model/averaging_bias.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {

std::string ExplainOptions::validate() const {
  if (!model_path.empty() && !baseline_path.empty()) return "give --model or --baseline, not both";
  if (!(min_stability >= 0 && min_stability <= 1)) return "min_stability must be in [0, 1]";
  if (!(heldout_leverage >= 1)) return str_cat("heldout_leverage = ", heldout_leverage, " must be at least 1 (a multiple of the mean training leverage)");
  if (auto p = input.validate(); !p.empty()) return p;
  if (auto p = support_check.validate(); !p.empty()) return p;
  return selection.validate();
}

namespace {

const double kDph = units::radps_to_dph(1.0);  // deg/h per rad/s

// Over the training samples, or over the held-out samples that confirm (inside the training support).
double rms(const Eigen::VectorXd& r, const ExplainInput& in, bool heldout) {
  double s = 0.0;
  int n = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (heldout ? in.confirms(i) : in.heldout[static_cast<std::size_t>(i)] == 0) s += r(i) * r(i), ++n;
  }
  return n ? std::sqrt(s / n) : 0.0;
}

// Every effect's candidates on this recording, restricted to `list` (comma-separated ids; empty: all).
// Auxiliary channels stay whatever the list: they localise what no effect explains.
std::vector<Candidate> propose_candidates(const ModelSpec& base, const ExplainInput& in, const std::string& list,
                                          std::vector<std::string>* untestable) {
  std::vector<std::string> keep;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    if (!effect_registry().find(item)) fail("--effects: unknown effect '", item, "'; known: ", effect_registry().known());
    keep.push_back(item);
  }
  const CandidateContext context(base.terms, base.lag_tau_s, in);
  std::vector<Candidate> out;
  for (const Effect* e : effect_library()) {
    Proposal p = e->propose(context);
    if (!p.untestable.empty()) untestable->push_back(str_cat(e->id(), ": ", p.untestable));
    const bool kept = keep.empty() || !e->is_physics() || std::find(keep.begin(), keep.end(), e->id()) != keep.end();
    if (kept) out.insert(out.end(), p.candidates.begin(), p.candidates.end());
  }
  return out;
}

// The accepted model: the base plus every judged effect that passed; the rest demoted, with the reason.
struct Accepted {
  ModelSpec model;
  bool lag_selected = false;
  std::vector<Judged> effects;
  std::vector<DemotedEffect> demoted;
};

// Its predictive z on its own support, when the held-out blocks do not hold it and the check could test it.
std::optional<double> support_z(const Judged& j) {
  return !j.heldout_holds && j.support && j.support->testable ? std::optional<double>(j.support->z) : std::nullopt;
}

// Why a judged effect is not accepted.
std::string demotion_reason(const Judged& j, double min_stability, double untested_bic) {
  if (j.stability < min_stability) return "unstable across training blocks";
  if (j.rivalled_by_further_component(untested_bic)) {
    return str_cat("an alternative of ", j.further->of, ": a second time constant of it (", format_significant(j.further->tau_s, 3),
                   " s, the first refitted to ", format_significant(j.further->first_tau_s, 3), " s) explains the same (dBIC of ",
                   j.effect.score.id, " over it ", format_significant(j.further->delta_bic, 3), " < ", format_significant(untested_bic, 3), ")");
  }
  if (j.explained_by_others()) {
    return str_cat("explained by the other effects once their nonlinear parameters are refitted without it (profile dBIC ",
                   format_significant(*j.profiled_delta_bic, 3), ")");
  }
  if (j.weak_and_untested(untested_bic)) {
    return str_cat("the held-out blocks ", j.heldout_holds ? "cannot test it" : "do not hold it",
                   " and its evidence against the coloured noise re-estimated with it is weak (dBIC ",
                   format_significant(j.effect.score.ml_delta_bic, 3), " < ", format_significant(untested_bic, 3), ")");
  }
  if (!j.heldout_holds) {
    return str_cat("not confirmed on its own support (the held-out blocks do not hold it): predictive z ", format_significant(j.support->z, 3),
                   " over ", j.support->samples, " training samples, t ", format_significant(j.support->t_start_s, 4), "-",
                   format_significant(j.support->t_end_s, 4), " s");
  }
  return "not confirmed on the held-out blocks";
}

Accepted accept(const std::vector<Judged>& judged, const ModelSpec& base, const SelectionResult& sel, double min_stability, double untested_bic) {
  Accepted a{base, false, {}, {}};
  for (const auto& j : judged) {
    if (!j.accepted(min_stability, untested_bic)) {
      const auto z = j.heldout_testable && j.heldout_holds ? std::optional<double>(j.heldout_z) : std::nullopt;
      if (j.stability >= min_stability && j.rivalled_by_further_component(untested_bic)) {
        for (Judged& other : a.effects) {
          if (other.effect.score.id == j.further->of) other.effect.alternatives.push_back(j.effect.score.id);
        }
      }
      a.demoted.push_back({j.effect.score.id, j.effect.score.delta_bic, j.stability, j.heldout_gain, z, support_z(j), demotion_reason(j, min_stability, untested_bic)});
      continue;
    }
    if (j.term) a.model.terms.push_back(*j.term);
    else a.model.lag_tau_s = sel.model.lag_tau_s, a.lag_selected = true;
    a.effects.push_back(j);
  }
  return a;
}

// The judging's profile of the accepted model, if it made one: the selected model's when nothing was
// demoted, the selected model without the one demoted effect otherwise - the refit starts at its optimum.
std::optional<ProfiledFit> profiled_start(const Judgement& judgement, const Accepted& accepted) {
  std::optional<ProfiledFit> p;
  if (accepted.demoted.empty()) p = judgement.full;
  for (const auto& j : judgement.effects) {
    if (accepted.demoted.size() == 1 && j.effect.score.id == accepted.demoted.front().id) p = j.profiled_without;
  }
  if (!p || p->nonlinear == 0 || p->model.terms.size() != accepted.model.terms.size()) return std::nullopt;
  return p;
}

// The refitted model: SI coefficients, the prior's column becoming its gain.
std::unique_ptr<ExplainedModel> refitted_model(const RefitResult& fit, const TermScaling& scaling, std::unique_ptr<CalibrationModel> prior) {
  std::vector<Term> terms;
  std::vector<double> coefs;
  double prior_gain = 1.0;
  Eigen::Index at = 0;
  for (const auto& t : fit.model.terms) {
    const auto channels = t->channels();
    if (t.as<ChannelTerm>() && channels.size() == 1 && channels[0] == kPriorChannel) {
      prior_gain = fit.beta(at) / kDph;
    } else {
      terms.push_back(t);
      for (int c = 0; c < t.size(); ++c) coefs.push_back(fit.beta(at + c) / kDph);
    }
    at += t.size();
  }
  return std::make_unique<ExplainedModel>(scaling, fit.model.lag_tau_s, terms,
                                          Eigen::Map<const Eigen::VectorXd>(coefs.data(), static_cast<Eigen::Index>(coefs.size())),
                                          std::move(prior), prior_gain);
}

// The held-out rms without a judged effect and the share of the held-out excess over the noise floor it removes.
void heldout_excess(const Judged& j, double floor_dph, FoundEffect& f) {
  if (j.heldout_samples == 0) return;
  const double n = static_cast<double>(j.heldout_samples), without = j.heldout_rss_without / n, floor2 = floor_dph * floor_dph;
  f.heldout_rms_without_dph = std::sqrt(without);
  if (without - floor2 > 0.05 * floor2) f.heldout_excess_removed = j.heldout_gain / n / (without - floor2);
}

// The physical parameters of each accepted effect from the refit, its alternatives and evidence; effects
// that are not physics (a channel) become unexplained structure localised to that channel.
void report_effects(const Accepted& accepted, std::size_t base_terms, const RefitResult& fit, const TermScaling& scaling,
                    const ExplainInput& in, double floor_dph, ExplainSummary& out) {
  std::vector<Eigen::Index> term_start;
  Eigen::Index at = 0;
  for (const auto& t : fit.model.terms) term_start.push_back(at), at += t.size();
  std::size_t term = base_terms;
  for (const auto& j : accepted.effects) {
    const SelectedEffect& s = j.effect;
    const Effect& effect = *s.candidate.effect;
    std::vector<PhysicalParameter> params;
    const int this_term = j.term ? static_cast<int>(term++) : -1;
    if (j.term) {
      const Term& t = fit.model.terms[static_cast<std::size_t>(this_term)];
      const Eigen::Index s0 = term_start[static_cast<std::size_t>(this_term)];
      params = effect.parameters(t, fit.beta.segment(s0, t.size()), fit.beta_sigma.segment(s0, t.size()), scaling);
    }
    for (const auto& nl : fit.nonlinear) {
      if (nl.term == this_term) params.push_back({nl.name, nl.value, nl.low, nl.high, false});
    }
    if (j.term) {
      const auto p = fit.model.terms[static_cast<std::size_t>(this_term)].parameter();
      if (p && !p->scale) params.push_back(PhysicalParameter::reference_value(p->name, p->value));
    }
    if (!effect.is_physics()) {
      Unexplained u;
      u.kind = parse_enum<UnexplainedKind>(effect.unexplained_kind(), "unexplained kind");
      const auto channels = (*s.candidate.term)->channels();
      if (!channels.empty()) u.channel = channels.front();
      const auto at = fit.model.terms[static_cast<std::size_t>(this_term)].parameter();
      const bool located = at && !at->scale;  // a change point: its time, or the held-out run it lies in
      u.t_start_s = located ? at->value : in.signals.t_s.front(), u.t_end_s = located ? at->value : in.signals.t_s.back();
      if (const auto run = located ? in.heldout_run_at(at->value) : std::nullopt) {
        const auto t = [&](Eigen::Index i) { return in.signals.t_s[static_cast<std::size_t>(std::min(i, in.size() - 1))]; };
        u.t_start_s = std::min(at->value, t(run->first)), u.t_end_s = std::max(at->value, t(run->second + 1));
      }
      u.statistic = s.score.delta_bic, u.p_value = s.score.p_value, u.parameters = params;
      out.unexplained.push_back(u);
      continue;
    }
    FoundEffect f{std::string(effect.id()), std::string(effect.description()), params, s.score.delta_bic, s.score.p_value,
                  s.alternatives, s.weaker_alternatives, {}, j.stability, std::nullopt, 0.0, std::nullopt, std::nullopt};
    for (const auto* group : {&s.alternatives, &s.weaker_alternatives}) {
      for (const auto& a : *group) f.separating.push_back({a, separating_experiment(effect, find_effect(a))});
    }
    if (j.heldout_testable && j.heldout_holds) f.heldout_z = j.heldout_z;
    f.support_z = support_z(j);
    heldout_excess(j, floor_dph, f);
    out.effects.push_back(f);
  }
}

// The model with its flexible scale factor made smooth: every surface replaced by the polynomial
// omega dT^i u^j, i <= 3, j <= rate_order (the baseline family's polynomial form at order 3), and the rate
// orders above rate_order (up to 3) dropped from every polynomial. The kind of the term that changed first;
// empty when nothing changed (no core).
std::string smooth_core(const ModelSpec& model, int rate_order, ModelSpec& core) {
  core.terms.clear(), core.lag_tau_s = model.lag_tau_s;
  std::string changed;
  for (const Term& t : model.terms) {
    if (t.as<ScaleFactorSurface>()) {
      ScaleFactorPolynomial::Orders sf;
      for (int i = 0; i <= 3; ++i)
        for (int j = 0; j <= rate_order; ++j) sf.push_back({i, j});
      core.terms.push_back(scale_factor_polynomial(sf));
      if (changed.empty()) changed = "scale_factor_surface";
      continue;
    }
    const auto* p = t.as<ScaleFactorPolynomial>();
    std::vector<int> kept;
    for (int c = 0; p && c < t.size(); ++c) {
      const int j = p->orders()[static_cast<std::size_t>(c)][1];
      if (j <= rate_order || j > 3) kept.push_back(c);
    }
    if (!p || kept.size() == static_cast<std::size_t>(t.size())) {
      core.terms.push_back(t);
      continue;
    }
    if (const std::optional<Term> smooth = t.subset(kept)) core.terms.push_back(*smooth);
    if (changed.empty()) changed = "scale_factor_polynomial";
  }
  return changed;
}

// Physics the accepted model's flexible scale factor absorbs: every candidate not found, tested against the
// model with that flexibility made smooth (at the candidate's core_rate_order). Strong there (dBIC >
// ambiguity_bic) and weak against the model itself (dBIC < ambiguity_bic): an alternative explanation of
// part of the scale factor, with the experiment that would separate them where the effect knows it.
std::vector<AbsorbedAlternative> absorbed_alternatives(const std::vector<Candidate>& candidates, const Accepted& accepted,
                                                       const ExplainInput& in, const Eigen::VectorXd& y, const TermScaling& scaling,
                                                       const Whitener& w, double ambiguity_bic) {
  std::map<int, std::vector<Candidate>> open;  // by core rate order: one core fitted per order
  for (const Candidate& c : candidates) {
    const bool found = std::any_of(accepted.effects.begin(), accepted.effects.end(), [&](const Judged& j) { return j.effect.candidate.id() == c.id(); });
    if (!found && c.effect->is_physics() && !c.further_component) open[c.effect->core_rate_order()].push_back(c);
  }
  std::vector<AbsorbedAlternative> out;
  for (const auto& [order, group] : open) {
    ModelSpec core;
    const std::string absorbed_by = smooth_core(accepted.model, order, core);
    if (absorbed_by.empty()) continue;
    const std::vector<AbsorptionTest> tests = absorption_tests(group, accepted.model, core, in, y, scaling, w);
    for (std::size_t k = 0; k < group.size(); ++k) {
      const AbsorptionTest& t = tests[k];
      if (!(t.delta_bic_core > ambiguity_bic && t.delta_bic_full < ambiguity_bic)) continue;
      const std::string what = absorbed_by == "scale_factor_surface" ? "scale-factor surface" : "scale-factor polynomial";
      std::string reason = str_cat("the ", what, " absorbs it: ", format_significant(100.0 * (1.0 - t.unique_fraction), 3),
                                   " % of its signal lies inside the simulation's span, so against the simulation its dBIC is ",
                                   format_significant(t.delta_bic_full, 3), " (against a smooth scale factor of rate order ", order,
                                   " ", format_significant(t.delta_bic_core, 3), ")");
      if (t.delta_bic_over_flexibility > ambiguity_bic) {
        reason += str_cat("; with it, that smooth scale factor fits better than the ", what, " (BIC lower by ",
                          format_significant(t.delta_bic_over_flexibility, 3), "): the data prefer it to that flexibility");
      }
      out.push_back({std::string(group[k].id()), absorbed_by, t.unique_fraction, t.delta_bic_core, t.delta_bic_full,
                     t.delta_bic_over_flexibility, reason, group[k].effect->separating_experiment(absorbed_by)});
    }
  }
  return out;
}

// Significant structure left after the refit: channel correlations, time windows, (T, omega) cells.
void localise_unexplained(const Diagnostics& after, const ExplainInput& in, std::vector<Unexplained>& out) {
  const double t0 = in.signals.t_s.front(), t1 = in.signals.t_s.back();
  for (const auto& c : after.channels) {
    if (!c.significant) continue;
    Unexplained u;
    u.kind = UnexplainedKind::correlation, u.channel = c.channel, u.t_start_s = t0, u.t_end_s = t1;
    u.statistic = c.peak_r, u.lag_s = c.peak_lag_s, u.threshold = c.threshold;
    out.push_back(u);
  }
  for (const auto& win : after.windows) {
    if (!(std::abs(win.z) > after.window_threshold && after.windows.size() > 1)) continue;
    Unexplained u;
    u.kind = UnexplainedKind::time_window, u.t_start_s = win.t_start_s, u.t_end_s = win.t_end_s, u.statistic = win.z, u.mean_dph = win.mean_dph;
    out.push_back(u);
  }
  for (const auto& g : after.cells) {
    if (!(std::abs(g.z) > after.cell_threshold)) continue;
    Unexplained u;
    u.kind = UnexplainedKind::temperature_rate_cell, u.t_start_s = g.t_start_s, u.t_end_s = g.t_end_s, u.statistic = g.z;
    u.temp_c = {g.temp_lo_c, g.temp_hi_c}, u.rate_dps = {g.rate_lo_dps, g.rate_hi_dps}, u.heating = g.heating, u.mean_dph = g.mean_dph;
    out.push_back(u);
  }
}

RecordingSummary recording_summary(const ExplainInput& in, const ExplainOptions& o) {
  RecordingSummary r;
  r.source = in.source, r.axis = o.input.axis;
  r.samples = static_cast<long>(in.size()), r.training_samples = static_cast<long>(in.training_size());
  r.duration_s = in.signals.t_s.back() - in.signals.t_s.front();
  r.blocks = in.blocks, r.thermal_cycles = in.thermal_cycles, r.heldout_every = o.input.heldout_every;
  r.heldout_outside_support = static_cast<long>(std::count(in.outside_support.begin(), in.outside_support.end(), 1));
  r.skipped_channels = in.skipped;
  r.temperature_recorded = in.temperature_recorded;
  return r;
}

// The noise models of the residuals before and after the refit, from their training samples (Allan fit, then
// maximum likelihood), and their diagnostics; returns the final (after) noise model.
NoiseModel diagnose_before_and_after(const ExplainResult& result, double alpha, ExplainSummary& summary) {
  const ExplainInput& in = result.input;
  std::vector<Eigen::Index> training_rows;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (!in.heldout[static_cast<std::size_t>(i)]) training_rows.push_back(i);
  }
  const auto runs = contiguous_runs(training_rows, in.segment);
  const auto noise_of = [&](const Eigen::VectorXd& r) {
    return likelihood_noise_model(r, training_rows, in.signals.t_s, fit_noise_model(r, runs, in.dt_s, NoiseStart::gauss_markov_start));
  };
  const NoiseModel final_noise = noise_of(result.residual_after_dph);
  summary.before = diagnose(in, result.residual_before_dph, noise_of(result.residual_before_dph), alpha);
  summary.after = diagnose(in, result.residual_after_dph, final_noise, alpha);
  return final_noise;
}

}  // namespace

std::vector<std::string> explain_spread_columns(const std::vector<std::string>& names, const std::string& axis) {
  const GyroColumns g = gyro_columns(names, axis, "explain");
  std::vector<std::string> out{g.ref};
  if (!g.temp.empty()) out.push_back(g.temp);
  return out;
}

ExplainResult explain_recording(const Recording& rec, const ExplainOptions& o, Checkpoint* checkpoint, const Decimation* decimation) {
  if (auto p = o.validate(); !p.empty()) fail("explain: ", p);
  const auto start = std::chrono::steady_clock::now();
  ExplainResult result;
  StageClock clock(result.summary.stage_times, "explain: ");
  result.input = load_input(rec, o.input);
  ExplainInput& in = result.input;
  const TermScaling scaling = TermScaling::of(in.signals);
  const Eigen::VectorXd y = in.error * kDph;
  ExplainSummary& summary = result.summary;

  // 1. The simulation and the structure whose coefficients are re-estimated.
  Simulation sim = make_simulation(in, o.model_path, o.baseline_path, o.baseline_form, o.input);
  const ModelSpec& base = sim.base;
  HeldoutSupport support(in, base, scaling, o.heldout_leverage);
  in.outside_support = support.baseline();
  result.simulation_residual_dph = sim.prior ? Eigen::VectorXd(y - in.signals.channel(kPriorChannel) * kDph) : y;
  clock.lap("input and simulation");

  // 2. Candidates and forward selection.
  std::vector<std::string> untestable;
  const std::vector<Candidate> candidates = propose_candidates(base, in, o.effects, &untestable);
  const SelectionResult sel = select_effects(in, y, base, scaling, candidates, o.selection, checkpoint);
  const Whitener w = training_whitener(in, sel.noise);
  clock.lap("candidates and selection");

  // 3. Stability and held-out confirmation of every selected effect; 4. the joint refit with intervals.
  const Judgement judgement = judge_effects(in, y, base, sel, scaling, w, support, candidates, o.support_check);
  const Accepted accepted = accept(judgement.effects, base, sel, o.min_stability, o.selection.ambiguity_bic);
  clock.lap("judging (stability, held-out, profiles)");
  const std::optional<ProfiledFit> profile = profiled_start(judgement, accepted);
  const RefitResult final_fit = refit(in, y, profile ? profile->model : accepted.model, accepted.lag_selected, scaling, w, profile && profile->converged);
  clock.lap("refit");
  summary.absorbed_alternatives = absorbed_alternatives(candidates, accepted, in, y, scaling, w, o.selection.ambiguity_bic);
  clock.lap("absorbed alternatives");
  const Eigen::MatrixXd x_before = model_columns(base, in.signals, scaling);
  result.residual_before_dph = y - x_before * gls(x_before, y, w).beta;
  result.residual_after_dph = y - model_columns(final_fit.model, in.signals, scaling) * final_fit.beta;
  // The reported held-out fit compares the baseline with the refitted model where neither extrapolates.
  in.outside_support = support.outside({&final_fit.model});

  const NoiseModel final_noise = diagnose_before_and_after(result, o.selection.alpha, summary);
  clock.lap("noise models and diagnostics");

  // 5. The refitted model, the effects and what is left unexplained.
  result.model = refitted_model(final_fit, scaling, std::move(sim.prior));
  report_effects(accepted, base.terms.size(), final_fit, scaling, in, final_noise.stationary_sigma(), summary);
  localise_unexplained(summary.after, in, summary.unexplained);
  summary.verdict = !summary.effects.empty()      ? Verdict::missing_physics
                    : !summary.unexplained.empty() ? Verdict::unexplained_residual
                                                   : Verdict::no_missing_physics;
  summary.noise = {summary.after.noise_terms, final_noise, final_noise.stationary_sigma()};
  summary.fit = {rms(result.simulation_residual_dph, in, false), rms(result.residual_before_dph, in, false),
                 rms(result.residual_after_dph, in, false), rms(result.residual_before_dph, in, true),
                 rms(result.residual_after_dph, in, true), "ceres", final_fit.termination, final_fit.iterations, final_fit.covariance_ok};
  summary.recording = recording_summary(in, o);
  if (decimation && decimation->applied()) {
    const Dataset data = dataset_of(in, result.model->features());
    summary.recording.decimation = decimation_summary(*decimation, averaging_bias(*result.model, data, *decimation, summary.fit.rms_after_dph));
  }
  summary.simulation = sim.description;
  summary.selection = {o.selection.alpha, sel.bootstrap, o.selection.seed, sel.steps, untestable, sel.noise};
  summary.demoted = accepted.demoted;
  clock.lap("report");
  for (const auto& [stage, s] : sel.times.seconds) summary.stage_times.add(str_cat("selection: ", stage), s);
  summary.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace gyrosid::explain
