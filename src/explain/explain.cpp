#include "explain/explain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/units.h"
#include "explain/linear_fit.h"
#include "explain/refit.h"

namespace gyrosid::explain {

std::string ExplainOptions::validate() const {
  if (!model_path.empty() && !baseline_path.empty()) return "give --model or --baseline, not both";
  if (!(min_stability >= 0 && min_stability <= 1)) return "min_stability must be in [0, 1]";
  if (auto p = input.validate(); !p.empty()) return p;
  return selection.validate();
}

namespace {

constexpr const char* kPrior = "__prior";
const double kDph = units::radps_to_dph(1.0);  // deg/h per rad/s

// A model's inputs along the explained gyro, with the reference rate in place of the measured one: a
// prediction from the noisy output would carry the noise (times the scale factor), and a free gain on it
// would fit noise.
Dataset dataset_of(const ExplainInput& in, const std::vector<std::string>& features) {
  Dataset d;
  d.features = features;
  d.t_s = in.signals.t_s;
  d.measured = in.signals.rate;
  d.reference = in.signals.rate;
  d.target = in.error;
  d.x.resize(in.size(), static_cast<Eigen::Index>(features.size()));
  const CoilTemperature probe = coil_temperature(in.signals, 0.0);
  for (std::size_t f = 0; f < features.size(); ++f) {
    const auto col = static_cast<Eigen::Index>(f);
    if (features[f] == "measured_rate") d.x.col(col) = in.signals.rate;
    else if (features[f] == "temperature") d.x.col(col) = in.signals.temp_c;
    else if (features[f] == "temperature_rate") d.x.col(col) = probe.rate_c_per_s;
    else d.x.col(col) = in.signals.channel(features[f]);
  }
  return d;
}

// Generalised least squares on a set of rows: the whitened fit and its coefficients.
struct RowFit {
  Eigen::VectorXd beta;
  double rss = 0.0;
  std::size_t n = 0;
  int rank = 0;
};

RowFit gls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& w) {
  const WhitenedFit f = fit_whitened(w.apply(x), w.apply(y));
  return {f.beta, f.rss, static_cast<std::size_t>(f.residual.size()), f.rank};
}

Whitener rows_whitener(const ExplainInput& in, const NoiseModel& noise, const std::function<bool(Eigen::Index)>& keep) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (keep(i)) rows.push_back(i);
  }
  return Whitener(noise, rows, in.signals.t_s);
}

Eigen::MatrixXd columns(const ModelSpec& m, const ExplainInput& in, const TermScaling& sc) {
  return design_matrix(m.terms, in.signals, coil_temperature(in.signals, m.lag_tau_s), sc);
}

// Sum of squared residuals of predictions on the held-out rows (unwhitened: a user's view of the fit).
double heldout_rss(const Eigen::VectorXd& residual, const ExplainInput& in) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (in.heldout[static_cast<std::size_t>(i)]) s += residual(i) * residual(i);
  }
  return s;
}

double rms(const Eigen::VectorXd& r, const ExplainInput& in, bool heldout) {
  double s = 0.0;
  int n = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if ((in.heldout[static_cast<std::size_t>(i)] != 0) == heldout) s += r(i) * r(i), ++n;
  }
  return n ? std::sqrt(s / n) : 0.0;
}

std::string axis_of(const std::string& channel) {
  for (const char* a : {"_x_", "_y_", "_z_"}) {
    if (channel.find(a) != std::string::npos) return std::string(1, a[1]);
  }
  return channel;
}

// Physical parameters of an effect from its columns' coefficients (deg/h per column unit) and sigmas.
void physical_parameters(EffectId id, const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma, const TermScaling& sc,
                         nlohmann::json& params, nlohmann::json& ci) {
  const Term* term = &t;
  const double to_ratio = units::dph_to_radps(1.0);  // deg/h per (rad/s) -> rad/s per rad/s
  auto put = [&](const std::string& name, double value, double sd) {
    params[name] = value;
    ci[name] = {value - 1.96 * sd, value + 1.96 * sd};
  };
  switch (id) {
    case EffectId::temperature_bias:
      for (std::size_t c = 0; c < term->orders.size(); ++c) {
        const int k = term->orders[c];
        const double f = 1.0 / std::pow(sc.t_scale_c, k);
        put(k == 1 ? "c1_dph_per_c" : str_cat("c", k, "_dph_per_c", k), beta(static_cast<Eigen::Index>(c)) * f, sigma(static_cast<Eigen::Index>(c)) * f);
      }
      params["t_ref_c"] = sc.t_ref_c;
      break;
    case EffectId::shupe: put("k_dph_per_cpm", beta(0) / 60.0, sigma(0) / 60.0); break;
    case EffectId::thermal_hysteresis: put("offset_dph", beta(0), sigma(0)); break;
    case EffectId::warmup_transient: put("amplitude_dph", beta(0), sigma(0)); break;
    case EffectId::aging_trend: put("k_dph_per_h", beta(0), sigma(0)); break;
    case EffectId::scale_factor_asymmetry: put("asymmetry_ppm", 2e6 * beta(0) * to_ratio, 2e6 * sigma(0) * to_ratio); break;
    case EffectId::scale_factor_nonlinearity:
    case EffectId::scale_factor_temperature:
      for (std::size_t c = 0; c < term->sf_orders.size(); ++c) {
        const auto [i, j] = term->sf_orders[c];
        const double f = 1e6 * to_ratio / std::pow(sc.t_scale_c, i);
        const std::string name = i == 0 ? str_cat("k_u", j, "_ppm") : str_cat("k_t", i, "_u", j, i == 1 ? "_ppm_per_c" : str_cat("_ppm_per_c", i));
        put(name, beta(static_cast<Eigen::Index>(c)) * f, sigma(static_cast<Eigen::Index>(c)) * f);
      }
      params["rate_scale_dps"] = units::radps_to_dps(sc.rate_scale_radps);
      params["t_ref_c"] = sc.t_ref_c;
      break;
    case EffectId::g_sensitivity:
      for (std::size_t c = 0; c < term->channels.size(); ++c) {
        put("k_" + axis_of(term->channels[c]) + "_dph_per_g", beta(static_cast<Eigen::Index>(c)) * units::kStandardGravity,
            sigma(static_cast<Eigen::Index>(c)) * units::kStandardGravity);
      }
      break;
    case EffectId::g2_sensitivity:
      for (std::size_t c = 0; c < term->channels.size(); ++c) {
        const double g2 = units::kStandardGravity * units::kStandardGravity;
        put("k_" + axis_of(term->channels[c]) + "_dph_per_g2", beta(static_cast<Eigen::Index>(c)) * g2, sigma(static_cast<Eigen::Index>(c)) * g2);
      }
      break;
    case EffectId::magnetic_sensitivity:
      for (std::size_t c = 0; c < term->channels.size(); ++c) {
        put("k_" + term->channels[c].substr(0, term->channels[c].size() - 3) + "_dph_per_ut", beta(static_cast<Eigen::Index>(c)),
            sigma(static_cast<Eigen::Index>(c)));
      }
      break;
    case EffectId::cross_axis_coupling:
      for (std::size_t c = 0; c < term->channels.size(); ++c) {
        put("k_" + axis_of(term->channels[c]) + "_mrad", 1e3 * beta(static_cast<Eigen::Index>(c)) * to_ratio,
            1e3 * sigma(static_cast<Eigen::Index>(c)) * to_ratio);
      }
      break;
    case EffectId::auxiliary_channel: {
      const std::string& c = term->channels[0];
      const auto underscore = c.rfind('_');
      put("k_dph_per_" + (underscore == std::string::npos ? std::string("unit") : c.substr(underscore + 1)), beta(0), sigma(0));
      break;
    }
    case EffectId::thermal_lag: break;
  }
}

struct Judged {
  SelectedEffect effect;
  std::optional<Term> term;      // the effect's term in the selected model; none for the thermal lag
  double stability = 1.0;        // fraction of leave-one-training-block-out refits with dBIC > 0
  double heldout_gain = 0.0;     // held-out sum of squares without the effect minus with it, (deg/h)^2
  double heldout_z = 0.0;        // that gain in the whitened held-out samples over its standard error
  bool heldout_testable = false; // the held-out blocks see the effect (the two predictions differ there)

  // Kept if it survives the leave-one-block-out refits and, where the held-out blocks can judge it, improves
  // them significantly (z > 2: the gain |d|^2 + 2 r'd against its noise 2 sigma |d|).
  bool accepted(double min_stability) const { return stability >= min_stability && (!heldout_testable || heldout_z > 2.0); }
};

std::vector<Judged> judge_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base, const SelectionResult& sel,
                                  const TermScaling& scaling, const Whitener& w) {
  std::vector<int> training_blocks;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    const int b = in.block[static_cast<std::size_t>(i)];
    if (!in.heldout[static_cast<std::size_t>(i)] && std::find(training_blocks.begin(), training_blocks.end(), b) == training_blocks.end()) {
      training_blocks.push_back(b);
    }
  }
  const Eigen::MatrixXd x_full = columns(sel.model, in, scaling);
  const RowFit fit_full = gls(x_full, y, w);
  const Eigen::VectorXd residual_full = y - x_full * fit_full.beta;
  const double sigma = std::sqrt(fit_full.rss / std::max<double>(1.0, static_cast<double>(fit_full.n) - fit_full.rank));
  const Whitener heldout_w = rows_whitener(in, sel.noise, [&](Eigen::Index i) { return in.heldout[static_cast<std::size_t>(i)] != 0; });
  std::vector<Judged> out;
  std::size_t term = base.terms.size();
  for (std::size_t e = 0; e < sel.effects.size(); ++e) {
    Judged j{sel.effects[e], std::nullopt};
    const bool lag = j.effect.candidate.nonlinear == NonlinearParameter::lag_tau;
    // The selected model without this effect.
    ModelSpec minus = sel.model;
    if (lag) minus.lag_tau_s = base.lag_tau_s;
    else j.term = sel.model.terms[term], minus.terms.erase(minus.terms.begin() + static_cast<std::ptrdiff_t>(term++));
    const Eigen::MatrixXd x_minus = columns(minus, in, scaling);
    const RowFit fit_minus = gls(x_minus, y, w);
    const Eigen::VectorXd residual_minus = y - x_minus * fit_minus.beta;
    j.heldout_gain = heldout_rss(residual_minus, in) - heldout_rss(residual_full, in);
    const Eigen::VectorXd r = heldout_w.apply(residual_full), d = heldout_w.apply(residual_minus - residual_full);
    const double sigma_h = std::sqrt(r.squaredNorm() / std::max<double>(1.0, static_cast<double>(r.size())));
    j.heldout_testable = d.norm() / std::sqrt(static_cast<double>(std::max<Eigen::Index>(1, d.size()))) > 0.05 * sigma;
    j.heldout_z = d.norm() > 0 ? (d.squaredNorm() + 2.0 * r.dot(d)) / (2.0 * sigma_h * d.norm()) : 0.0;
    int kept = 0, tried = 0;
    for (int b : training_blocks) {
      if (tried == 8) break;
      const Whitener wb = rows_whitener(in, sel.noise, [&](Eigen::Index i) {
        return !in.heldout[static_cast<std::size_t>(i)] && in.block[static_cast<std::size_t>(i)] != b;
      });
      const RowFit f1 = gls(x_full, y, wb), f0 = gls(x_minus, y, wb);
      const double n = static_cast<double>(f1.n);
      const int k = std::max(1, f1.rank - f0.rank) + (lag || j.effect.candidate.nonlinear == NonlinearParameter::none ? 0 : 1);
      kept += n * std::log(f0.rss / f1.rss) - k * std::log(n) > 0;
      ++tried;
    }
    j.stability = tried ? static_cast<double>(kept) / tried : 1.0;
    out.push_back(j);
  }
  return out;
}

std::vector<Candidate> restrict_to(std::vector<Candidate> all, const std::string& list) {
  if (list.empty()) return all;
  std::vector<EffectId> keep;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) keep.push_back(parse_enum<EffectId>(item, "--effects"));
  }
  // Auxiliary channels stay: they localise what no effect explains.
  std::erase_if(all, [&](const Candidate& c) {
    return c.id != EffectId::auxiliary_channel && std::find(keep.begin(), keep.end(), c.id) == keep.end();
  });
  return all;
}

}  // namespace

ExplainResult explain_recording(const Recording& rec, const ExplainOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("explain: ", p);
  const auto start = std::chrono::steady_clock::now();
  ExplainResult result;
  result.input = load_input(rec, o.input);
  ExplainInput& in = result.input;
  const TermScaling scaling = TermScaling::of(in.signals);
  const Eigen::VectorXd y = in.error * kDph;

  // 1. The simulation and the structure whose coefficients are re-estimated.
  ModelSpec base;
  std::unique_ptr<CalibrationModel> prior;
  std::string simulation;
  if (!o.model_path.empty()) {
    prior = load_model(o.model_path);
    if (prior->target() != ModelTarget::error) fail(o.model_path, ": explain needs a model of the rate error (target error)");
    base.terms = structure_of(*prior, o.baseline_form, in.signals, &base.lag_tau_s);
    simulation = str_cat("model ", o.model_path, " (", prior->kind(), ")");
  } else if (!o.baseline_path.empty()) {
    // Fit the baseline family on the calibration recording; what it could identify is the simulation's
    // structure, what it could not (e.g. temperature terms from one plateau) stays a candidate.
    InputOptions io = o.input;
    const ExplainInput cal = load_input(read_recording(o.baseline_path), io);
    const TermScaling cal_scaling = TermScaling::of(cal.signals);
    const std::vector<Term> family = baseline_family(o.baseline_form, cal.signals);
    const Eigen::MatrixXd x = design_matrix(family, cal.signals, coil_temperature(cal.signals, 0.0), cal_scaling);
    const WhitenedFit f = fit_whitened(x, cal.error);
    std::vector<Term> kept;
    std::vector<double> coefs;
    int at = 0;
    for (const auto& t : family) {
      if (t.kind == TermKind::bias) {  // a bias always exists (0 if the recording cannot identify it)
        kept.push_back(t);
        coefs.push_back(f.beta(at++));
        continue;
      }
      if (t.kind == TermKind::scale_factor_surface) {  // grid values enter together: keep them all
        kept.push_back(t);
        for (int c = 0; c < t.size(); ++c, ++at) coefs.push_back(f.beta(at));
        continue;
      }
      Term k = t;
      k.orders.clear(), k.sf_orders.clear();
      for (int c = 0; c < t.size(); ++c, ++at) {
        if (!f.kept[static_cast<std::size_t>(at)]) continue;
        if (t.kind == TermKind::bias_temperature) k.orders.push_back(t.orders[static_cast<std::size_t>(c)]);
        if (t.kind == TermKind::scale_factor) k.sf_orders.push_back(t.sf_orders[static_cast<std::size_t>(c)]);
        coefs.push_back(f.beta(at));
      }
      if (k.size() > 0) kept.push_back(k);
    }
    base.terms = kept;
    prior = std::make_unique<ExplainedModel>(cal_scaling, 0.0, kept, Eigen::Map<const Eigen::VectorXd>(coefs.data(), static_cast<Eigen::Index>(coefs.size())));
    simulation = str_cat("baseline family fitted on ", o.baseline_path);
  } else {
    base.terms = baseline_family(o.baseline_form, in.signals);
    simulation = str_cat("baseline family (bias cubic in T, scale factor as a ",
                         base.terms.back().kind == TermKind::scale_factor_surface ? "bicubic surface over (T, omega)" : "polynomial of order 3 in T and omega",
                         ") fitted on the training blocks");
  }
  result.simulation_residual_dph = y;
  if (prior) {
    const Eigen::VectorXd p = prior->predict(dataset_of(in, prior->features()));
    in.signals.channels[kPrior] = p;
    result.simulation_residual_dph = y - p * kDph;
    base.terms.push_back(Term::on_channels({kPrior}));
  }
  const std::size_t base_terms = base.terms.size();

  // 2. Candidates and forward selection.
  std::vector<std::string> untestable;
  const std::vector<Candidate> candidates = restrict_to(make_candidates(base.terms, base.lag_tau_s, in, &untestable), o.effects);
  SelectionResult sel = select_effects(in, y, base, scaling, candidates, o.selection);
  const Whitener w = training_whitener(in, sel.noise);

  // 3. Stability (leave one training block out) and held-out confirmation of every selected effect.
  std::vector<Judged> judged = judge_effects(in, y, base, sel, scaling, w);
  ModelSpec model = base;
  bool lag_selected = false;
  nlohmann::json dropped = nlohmann::json::array();
  for (const auto& j : judged) {
    if (!j.accepted(o.min_stability)) {
      dropped.push_back({{"id", std::string(to_string(j.effect.candidate.id))}, {"stability", j.stability},
                         {"heldout_gain_dph2", j.heldout_gain}, {"heldout_z", j.heldout_z},
                         {"reason", j.stability < o.min_stability ? "unstable across training blocks" : "not confirmed on the held-out blocks"}});
      continue;
    }
    if (j.term) model.terms.push_back(*j.term);
    else model.lag_tau_s = sel.model.lag_tau_s, lag_selected = true;
  }
  std::erase_if(judged, [&](const Judged& j) { return !j.accepted(o.min_stability); });

  // 4. Joint refit (Ceres) with intervals; residuals before and after.
  const RefitResult final_fit = refit(in, y, model, lag_selected, scaling, w);
  const Eigen::MatrixXd x_before = columns(base, in, scaling);
  const RowFit fit_before = gls(x_before, y, w);
  result.residual_before_dph = y - x_before * fit_before.beta;
  result.residual_after_dph = y - columns(final_fit.model, in, scaling) * final_fit.beta;

  // The final noise model, from the final residual, and the diagnostics.
  std::vector<Eigen::Index> training_rows;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (!in.heldout[static_cast<std::size_t>(i)]) training_rows.push_back(i);
  }
  const auto runs = contiguous_runs(training_rows, in.segment);
  const NoiseModel final_noise = fit_noise_model(result.residual_after_dph, runs, in.dt_s);
  result.before = diagnose(in, result.residual_before_dph, fit_noise_model(result.residual_before_dph, runs, in.dt_s), o.selection.alpha);
  result.after = diagnose(in, result.residual_after_dph, final_noise, o.selection.alpha);

  // 5. The refitted model (SI coefficients; the prior's column becomes its gain) and the effects' report.
  std::vector<Term> model_terms;
  std::vector<double> model_coefs;
  std::vector<Eigen::Index> term_start;
  double prior_gain = 1.0;
  Eigen::Index at = 0;
  for (const auto& t : final_fit.model.terms) {
    term_start.push_back(at);
    if (t.kind == TermKind::channel && t.channels.size() == 1 && t.channels[0] == kPrior) {
      prior_gain = final_fit.beta(at) / kDph;
    } else {
      model_terms.push_back(t);
      for (int c = 0; c < t.size(); ++c) model_coefs.push_back(final_fit.beta(at + c) / kDph);
    }
    at += t.size();
  }
  nlohmann::json effects = nlohmann::json::array(), found_channels = nlohmann::json::array();
  std::size_t term = base_terms;
  for (const auto& j : judged) {
    const SelectedEffect& s = j.effect;
    nlohmann::json params = nlohmann::json::object(), ci = nlohmann::json::object();
    const int this_term = j.term ? static_cast<int>(term++) : -1;
    if (j.term) {
      const Term& t = final_fit.model.terms[static_cast<std::size_t>(this_term)];
      const Eigen::Index s0 = term_start[static_cast<std::size_t>(this_term)];
      physical_parameters(s.candidate.id, t, final_fit.beta.segment(s0, t.size()), final_fit.beta_sigma.segment(s0, t.size()), scaling, params, ci);
    }
    for (const auto& tc : final_fit.time_constants) {
      if (tc.term == this_term) params["tau_s"] = tc.tau_s, ci["tau_s"] = {tc.low_s, tc.high_s};
    }
    nlohmann::json alternatives = nlohmann::json::array(), weaker = nlohmann::json::array(), separating = nlohmann::json::array();
    for (EffectId a : s.alternatives) {
      alternatives.push_back(std::string(to_string(a)));
      separating.push_back({{"alternative", std::string(to_string(a))}, {"experiment", separating_experiment(s.candidate.id, a)}});
    }
    for (EffectId a : s.weaker_alternatives) {
      weaker.push_back(std::string(to_string(a)));
      separating.push_back({{"alternative", std::string(to_string(a))}, {"experiment", separating_experiment(s.candidate.id, a)}});
    }
    if (s.candidate.id == EffectId::auxiliary_channel) {
      // Not physics: the structure is unexplained, localised to the channel (and modelled on it).
      found_channels.push_back({{"channel", s.candidate.term.channels[0]}, {"t_start_s", in.signals.t_s.front()}, {"t_end_s", in.signals.t_s.back()},
                                {"statistic", s.score.delta_bic}, {"kind", "follows_channel"}, {"p_value", s.score.p_value},
                                {"parameters", params}, {"confidence", ci}});
      continue;
    }
    effects.push_back({{"id", std::string(to_string(s.candidate.id))},
                       {"description", std::string(describe(s.candidate.id))},
                       {"parameters", params},
                       {"confidence", ci},
                       {"delta_bic", s.score.delta_bic},
                       {"p_value", s.score.p_value},
                       {"alternatives", alternatives},
                       {"weaker_alternatives", weaker},
                       {"separating_experiments", separating},
                       {"stability", j.stability},
                       {"heldout_z", j.heldout_testable ? nlohmann::json(j.heldout_z) : nlohmann::json()},
                       {"heldout_confirmed", j.heldout_testable ? nlohmann::json(j.heldout_z > 2.0) : nlohmann::json()}});
  }
  std::unique_ptr<CalibrationModel> model_prior;
  if (!o.model_path.empty()) model_prior = load_model(o.model_path);
  else if (prior) model_prior = std::move(prior);
  result.model = std::make_unique<ExplainedModel>(scaling, final_fit.model.lag_tau_s, model_terms,
                                                  Eigen::Map<const Eigen::VectorXd>(model_coefs.data(), static_cast<Eigen::Index>(model_coefs.size())),
                                                  std::move(model_prior), prior_gain);

  // 6. Unexplained structure after the refit, and the verdict.
  nlohmann::json unexplained = found_channels;
  const double t0 = in.signals.t_s.front(), t1 = in.signals.t_s.back();
  for (const auto& c : result.after.channels) {
    if (c.significant) unexplained.push_back({{"channel", c.channel}, {"t_start_s", t0}, {"t_end_s", t1}, {"statistic", c.peak_r},
                                              {"kind", "correlation"}, {"lag_s", c.peak_lag_s}, {"threshold", c.threshold}});
  }
  for (const auto& win : result.after.windows) {
    if (std::abs(win.z) > result.after.window_threshold && result.after.windows.size() > 1) {
      unexplained.push_back({{"channel", nullptr}, {"t_start_s", win.t_start_s}, {"t_end_s", win.t_end_s}, {"statistic", win.z},
                             {"kind", "time_window"}, {"mean_dph", win.mean_dph}});
    }
  }
  for (const auto& g : result.after.cells) {
    if (std::abs(g.z) > result.after.cell_threshold) {
      unexplained.push_back({{"channel", nullptr}, {"t_start_s", g.t_start_s}, {"t_end_s", g.t_end_s}, {"statistic", g.z},
                             {"kind", "temperature_rate_cell"}, {"temp_c", {g.temp_lo_c, g.temp_hi_c}},
                             {"rate_dps", {g.rate_lo_dps, g.rate_hi_dps}}, {"branch", g.heating ? "heating" : "cooling"},
                             {"mean_dph", g.mean_dph}});
    }
  }
  const std::string verdict = !effects.empty() ? "missing_physics" : !unexplained.empty() ? "unexplained_residual" : "no_missing_physics";

  nlohmann::json noise_terms = nlohmann::json::array();
  for (const auto& t : result.after.noise_terms) {
    noise_terms.push_back({{"id", t.id}, {"description", std::string(describe_noise(t.id))}, {"coefficients", t.coefficients}});
  }
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& step : sel.steps) {
    nlohmann::json row = nlohmann::json::array();
    for (const auto& s : step) {
      nlohmann::json j = {{"id", std::string(to_string(s.id))}, {"columns", s.columns}, {"delta_bic", s.columns ? nlohmann::json(s.delta_bic) : nlohmann::json()},
                          {"p_value", s.p_value}, {"significant", s.significant}};
      if (!std::isnan(s.ml_delta_bic)) j["ml_delta_bic"] = s.ml_delta_bic;
      if (!std::isnan(s.tau_s)) j["tau_s"] = s.tau_s;
      row.push_back(j);
    }
    steps.push_back(row);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.summary = {
      {"verdict", verdict},
      {"effects", effects},
      {"noise", {{"terms", noise_terms}, {"whitening_model", final_noise.to_json()}, {"noise_floor_dph", final_noise.stationary_sigma()}}},
      {"unexplained", unexplained},
      {"fit",
       {{"rms_simulation_dph", rms(result.simulation_residual_dph, in, false)},
        {"rms_before_dph", rms(result.residual_before_dph, in, false)},
        {"rms_after_dph", rms(result.residual_after_dph, in, false)},
        {"heldout_rms_before_dph", rms(result.residual_before_dph, in, true)},
        {"heldout_rms_after_dph", rms(result.residual_after_dph, in, true)},
        {"refit", {{"solver", "ceres"}, {"termination", final_fit.termination}, {"iterations", final_fit.iterations},
                   {"covariance", final_fit.covariance_ok}}}}},
      {"recording", {{"source", in.source}, {"samples", in.size()}, {"training_samples", in.training_size()},
                     {"duration_s", t1 - t0}, {"blocks", in.blocks}, {"blocks_are_thermal_cycles", in.thermal_cycles},
                     {"axis", o.input.axis}, {"skipped_channels", in.skipped}}},
      {"simulation", simulation},
      {"selection", {{"alpha", o.selection.alpha}, {"bootstrap", o.selection.bootstrap}, {"seed", o.selection.seed},
                     {"steps", steps}, {"untestable", untestable}, {"dropped", dropped}, {"whitening_model", sel.noise.to_json()}}},
      {"diagnostics", {{"before", result.before.to_json()}, {"after", result.after.to_json()}}},
      {"run_time_s", seconds}};
  return result;
}

}  // namespace gyrosid::explain
