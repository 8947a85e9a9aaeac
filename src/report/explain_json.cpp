#include "report/explain_json.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace gyrosid {

using namespace explain;
using json = nlohmann::json;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// {"parameters": {name: value}, "confidence": {name: [low, high]}} (reference values have no interval).
void put_parameters(const std::vector<PhysicalParameter>& params, json& j) {
  json values = json::object(), ci = json::object();
  for (const auto& p : params) {
    values[p.name] = p.value;
    if (!p.reference) ci[p.name] = {p.low, p.high};
  }
  j["parameters"] = values, j["confidence"] = ci;
}

std::vector<PhysicalParameter> parameters_of(const json& j) {
  std::vector<PhysicalParameter> out;
  const json& ci = j.at("confidence");
  for (auto it = j.at("parameters").begin(); it != j.at("parameters").end(); ++it) {
    const double v = it.value().get<double>();
    if (ci.contains(it.key())) out.push_back({it.key(), v, ci[it.key()][0].get<double>(), ci[it.key()][1].get<double>(), false});
    else out.push_back(PhysicalParameter::reference_value(it.key(), v));
  }
  return out;
}

json effect_json(const FoundEffect& e) {
  json separating = json::array();
  for (const auto& s : e.separating) separating.push_back({{"alternative", s.alternative}, {"experiment", s.experiment}});
  json j = {{"id", e.id},
            {"description", e.description},
            {"delta_bic", e.delta_bic},
            {"p_value", e.p_value},
            {"alternatives", e.alternatives},
            {"weaker_alternatives", e.weaker_alternatives},
            {"separating_experiments", separating},
            {"stability", e.stability},
            {"heldout_z", e.heldout_z ? json(*e.heldout_z) : json()},
            {"heldout_confirmed", e.heldout_z ? json(e.heldout_confirmed()) : json()},
            {"heldout_rms_without_dph", e.heldout_rms_without_dph},
            {"heldout_excess_removed", e.heldout_excess_removed ? json(*e.heldout_excess_removed) : json()},
            {"support_z", e.support_z ? json(*e.support_z) : json()}};
  put_parameters(e.parameters, j);
  return j;
}

FoundEffect effect_of(const json& j) {
  FoundEffect e;
  e.id = j.at("id").get<std::string>(), e.description = j.at("description").get<std::string>();
  e.parameters = parameters_of(j);
  e.delta_bic = j.at("delta_bic").get<double>(), e.p_value = j.at("p_value").get<double>();
  e.alternatives = j.at("alternatives").get<std::vector<std::string>>();
  e.weaker_alternatives = j.at("weaker_alternatives").get<std::vector<std::string>>();
  for (const auto& s : j.at("separating_experiments")) e.separating.push_back({s.at("alternative"), s.at("experiment")});
  e.stability = j.at("stability").get<double>();
  if (!j.at("heldout_z").is_null()) e.heldout_z = j["heldout_z"].get<double>();
  e.heldout_rms_without_dph = j.at("heldout_rms_without_dph").get<double>();
  if (!j.at("heldout_excess_removed").is_null()) e.heldout_excess_removed = j["heldout_excess_removed"].get<double>();
  if (j.contains("support_z") && !j["support_z"].is_null()) e.support_z = j["support_z"].get<double>();
  return e;
}

json unexplained_json(const Unexplained& u) {
  json j = {{"channel", u.channel ? json(*u.channel) : json()}, {"t_start_s", u.t_start_s}, {"t_end_s", u.t_end_s},
            {"statistic", u.statistic}, {"kind", to_string(u.kind)}};
  switch (u.kind) {
    case UnexplainedKind::follows_channel:
    case UnexplainedKind::change_point:
    case UnexplainedKind::trend_change: j["p_value"] = u.p_value, put_parameters(u.parameters, j); break;
    case UnexplainedKind::correlation: j["lag_s"] = u.lag_s, j["threshold"] = u.threshold; break;
    case UnexplainedKind::time_window: j["mean_dph"] = u.mean_dph; break;
    case UnexplainedKind::temperature_rate_cell:
      j["temp_c"] = u.temp_c, j["rate_dps"] = u.rate_dps, j["branch"] = u.heating ? "heating" : "cooling", j["mean_dph"] = u.mean_dph;
      break;
  }
  return j;
}

Unexplained unexplained_of(const json& j) {
  Unexplained u;
  u.kind = parse_enum<UnexplainedKind>(j.at("kind").get<std::string>(), "explain.json unexplained kind");
  if (!j.at("channel").is_null()) u.channel = j["channel"].get<std::string>();
  u.t_start_s = j.at("t_start_s").get<double>(), u.t_end_s = j.at("t_end_s").get<double>(), u.statistic = j.at("statistic").get<double>();
  switch (u.kind) {
    case UnexplainedKind::follows_channel:
    case UnexplainedKind::change_point:
    case UnexplainedKind::trend_change: u.p_value = j.at("p_value").get<double>(), u.parameters = parameters_of(j); break;
    case UnexplainedKind::correlation: u.lag_s = j.at("lag_s").get<double>(), u.threshold = j.at("threshold").get<double>(); break;
    case UnexplainedKind::time_window: u.mean_dph = j.at("mean_dph").get<double>(); break;
    case UnexplainedKind::temperature_rate_cell:
      u.temp_c = j.at("temp_c").get<std::array<double, 2>>(), u.rate_dps = j.at("rate_dps").get<std::array<double, 2>>();
      u.heating = j.at("branch") == "heating", u.mean_dph = j.at("mean_dph").get<double>();
      break;
  }
  return u;
}

json score_json(const CandidateScore& s) {
  json j = {{"id", s.id}, {"columns", s.columns}, {"delta_bic", s.columns ? json(s.delta_bic) : json()}, {"p_value", s.p_value},
            {"significant", s.significant}};
  if (!std::isnan(s.held_delta_bic)) j["held_delta_bic"] = s.held_delta_bic;
  if (!std::isnan(s.ml_delta_bic)) j["ml_delta_bic"] = s.ml_delta_bic;
  if (!std::isnan(s.tau_s)) j["tau_s"] = s.tau_s;
  return j;
}

CandidateScore score_of(const json& j) {
  CandidateScore s;
  s.id = j.at("id").get<std::string>(), s.columns = j.at("columns").get<int>();
  s.delta_bic = j.at("delta_bic").is_null() ? -std::numeric_limits<double>::infinity() : j["delta_bic"].get<double>();
  s.p_value = j.at("p_value").get<double>(), s.significant = j.at("significant").get<bool>();
  s.held_delta_bic = j.value("held_delta_bic", kNan), s.ml_delta_bic = j.value("ml_delta_bic", kNan), s.tau_s = j.value("tau_s", kNan);
  return s;
}

json diagnostics_json(const Diagnostics& d) {
  json ch = json::array(), win = json::array(), cl = json::array();
  for (const auto& c : d.channels) {
    ch.push_back({{"channel", c.channel}, {"peak_r", c.peak_r}, {"peak_lag_s", c.peak_lag_s}, {"threshold", c.threshold}, {"significant", c.significant}});
  }
  for (const auto& t : d.windows) win.push_back({{"t_start_s", t.t_start_s}, {"t_end_s", t.t_end_s}, {"mean_dph", t.mean_dph}, {"z", t.z}});
  for (const auto& g : d.cells) {
    cl.push_back({{"temp_c", {g.temp_lo_c, g.temp_hi_c}}, {"rate_dps", {g.rate_lo_dps, g.rate_hi_dps}}, {"branch", g.heating ? "heating" : "cooling"},
                  {"samples", g.samples}, {"mean_dph", g.mean_dph}, {"z", g.z}});
  }
  return {{"ljung_box", {{"q", d.ljung_box_q}, {"lags", d.ljung_box_lags}, {"dof", d.ljung_box_dof}, {"p_value", d.ljung_box_p}}},
          {"noise_model", d.noise.to_json()},
          {"channels", ch},
          {"time_windows", {{"threshold_z", d.window_threshold}, {"windows", win}}},
          {"grid", {{"threshold_z", d.cell_threshold}, {"cells", cl}}}};
}

Diagnostics diagnostics_of(const json& j) {
  Diagnostics d;
  const json& lb = j.at("ljung_box");
  d.ljung_box_q = lb.at("q"), d.ljung_box_lags = lb.at("lags"), d.ljung_box_dof = lb.at("dof"), d.ljung_box_p = lb.at("p_value");
  d.noise = NoiseModel::from_json(j.at("noise_model"));
  for (const auto& c : j.at("channels")) d.channels.push_back({c.at("channel"), {}, {}, c.at("peak_r"), c.at("peak_lag_s"), c.at("threshold"), c.at("significant")});
  d.window_threshold = j.at("time_windows").at("threshold_z");
  for (const auto& t : j["time_windows"].at("windows")) d.windows.push_back({t.at("t_start_s"), t.at("t_end_s"), t.at("mean_dph"), t.at("z")});
  d.cell_threshold = j.at("grid").at("threshold_z");
  for (const auto& g : j["grid"].at("cells")) {
    GridCell c;
    c.temp_lo_c = g.at("temp_c")[0], c.temp_hi_c = g["temp_c"][1], c.rate_lo_dps = g.at("rate_dps")[0], c.rate_hi_dps = g["rate_dps"][1];
    c.heating = g.at("branch") == "heating", c.samples = g.at("samples"), c.mean_dph = g.at("mean_dph"), c.z = g.at("z");
    d.cells.push_back(c);
  }
  return d;
}

json noise_terms_json(const std::vector<NoiseTerm>& terms) {
  json out = json::array();
  for (const auto& t : terms) {
    json coefficients = json::object();
    for (const auto& [name, value] : t.coefficients) coefficients[name] = value;
    out.push_back({{"id", t.id}, {"description", std::string(describe_noise(t.id))}, {"coefficients", coefficients}});
  }
  return out;
}

json stage_times_json(const StageTimes& t) {
  json out = json::array();
  for (const auto& [stage, s] : t.seconds) out.push_back({{"stage", stage}, {"s", s}});
  return out;
}

json selection_json(const SelectionRecord& s) {
  json steps = json::array();
  for (const auto& step : s.steps) {
    json row = json::array();
    for (const auto& c : step) row.push_back(score_json(c));
    steps.push_back(row);
  }
  return {{"alpha", s.alpha}, {"bootstrap", s.bootstrap}, {"seed", s.seed}, {"steps", steps}, {"untestable", s.untestable},
          {"whitening_model", s.whitening.to_json()}};
}

SelectionRecord selection_of(const json& j) {
  SelectionRecord s;
  s.alpha = j.at("alpha"), s.bootstrap = j.at("bootstrap"), s.seed = j.at("seed");
  for (const auto& row : j.at("steps")) {
    s.steps.emplace_back();
    for (const auto& c : row) s.steps.back().push_back(score_of(c));
  }
  s.untestable = j.at("untestable").get<std::vector<std::string>>();
  s.whitening = NoiseModel::from_json(j.at("whitening_model"));
  return s;
}

json absorbed_json(const AbsorbedAlternative& a) {
  return {{"id", a.id}, {"absorbed_by", a.absorbed_by}, {"unique_fraction", a.unique_fraction}, {"delta_bic_core", a.delta_bic_core},
          {"delta_bic_full", a.delta_bic_full}, {"delta_bic_over_flexibility", a.delta_bic_over_flexibility},
          {"reason", a.reason}, {"separating_experiment", a.separating_experiment}};
}

AbsorbedAlternative absorbed_of(const json& j) {
  return {j.at("id"),          j.at("absorbed_by"), j.at("unique_fraction"),
          j.at("delta_bic_core"), j.at("delta_bic_full"), j.value("delta_bic_over_flexibility", 0.0), j.at("reason"),
          j.value("separating_experiment", "")};
}

json demoted_json(const DemotedEffect& d) {
  return {{"id", d.id}, {"delta_bic", d.delta_bic}, {"stability", d.stability}, {"heldout_gain_dph2", d.heldout_gain_dph2},
          {"heldout_z", d.heldout_z ? json(*d.heldout_z) : json()}, {"support_z", d.support_z ? json(*d.support_z) : json()}, {"reason", d.reason}};
}

DemotedEffect demoted_of(const json& j) {
  DemotedEffect d{j.at("id"), j.at("delta_bic"), j.at("stability"), j.at("heldout_gain_dph2"), std::nullopt, std::nullopt, j.at("reason")};
  if (!j.at("heldout_z").is_null()) d.heldout_z = j["heldout_z"].get<double>();
  if (j.contains("support_z") && !j["support_z"].is_null()) d.support_z = j["support_z"].get<double>();
  return d;
}

json fit_json(const FitSummary& f) {
  return {{"rms_simulation_dph", f.rms_simulation_dph},
          {"rms_before_dph", f.rms_before_dph},
          {"rms_after_dph", f.rms_after_dph},
          {"heldout_rms_before_dph", f.heldout_rms_before_dph},
          {"heldout_rms_after_dph", f.heldout_rms_after_dph},
          {"refit", {{"solver", f.refit_solver}, {"termination", f.refit_termination}, {"iterations", f.refit_iterations},
                     {"covariance", f.refit_covariance}}}};
}

FitSummary fit_of(const json& j) {
  FitSummary f;
  f.rms_simulation_dph = j.at("rms_simulation_dph"), f.rms_before_dph = j.at("rms_before_dph"), f.rms_after_dph = j.at("rms_after_dph");
  f.heldout_rms_before_dph = j.at("heldout_rms_before_dph"), f.heldout_rms_after_dph = j.at("heldout_rms_after_dph");
  const json& r = j.at("refit");
  f.refit_solver = r.at("solver"), f.refit_termination = r.at("termination"), f.refit_iterations = r.at("iterations"),
  f.refit_covariance = r.at("covariance");
  return f;
}

json recording_json(const RecordingSummary& r) {
  json j = {{"source", r.source}, {"samples", r.samples}, {"training_samples", r.training_samples}, {"duration_s", r.duration_s},
            {"blocks", r.blocks}, {"blocks_are_thermal_cycles", r.thermal_cycles}, {"heldout_every", r.heldout_every},
            {"heldout_outside_support", r.heldout_outside_support}, {"axis", r.axis}, {"skipped_channels", r.skipped_channels}};
  if (!r.temperature_recorded) j["temperature_recorded"] = false;
  if (!r.decimation.is_null()) j["decimation"] = r.decimation;
  return j;
}

RecordingSummary recording_of(const json& j) {
  RecordingSummary r;
  r.source = j.at("source"), r.samples = j.at("samples"), r.training_samples = j.at("training_samples"), r.duration_s = j.at("duration_s");
  r.blocks = j.at("blocks"), r.thermal_cycles = j.at("blocks_are_thermal_cycles"), r.heldout_every = j.value("heldout_every", 4);
  r.heldout_outside_support = j.value("heldout_outside_support", 0L);
  r.axis = j.at("axis"), r.skipped_channels = j.at("skipped_channels").get<std::vector<std::string>>();
  r.temperature_recorded = j.value("temperature_recorded", true);
  if (j.contains("decimation")) r.decimation = j["decimation"];
  return r;
}

}  // namespace

json to_json(const ExplainSummary& s) {
  json effects = json::array(), demoted = json::array(), unexplained = json::array();
  for (const auto& e : s.effects) effects.push_back(effect_json(e));
  for (const auto& d : s.demoted) demoted.push_back(demoted_json(d));
  json absorbed = json::array();
  for (const auto& a : s.absorbed_alternatives) absorbed.push_back(absorbed_json(a));
  for (const auto& u : s.unexplained) unexplained.push_back(unexplained_json(u));
  return {{"verdict", to_string(s.verdict)},
          {"effects", effects},
          {"demoted", demoted},
          {"absorbed_alternatives", absorbed},
          {"noise", {{"terms", noise_terms_json(s.noise.terms)}, {"whitening_model", s.noise.whitening.to_json()}, {"noise_floor_dph", s.noise.floor_dph}}},
          {"unexplained", unexplained},
          {"fit", fit_json(s.fit)},
          {"recording", recording_json(s.recording)},
          {"simulation", s.simulation},
          {"selection", selection_json(s.selection)},
          {"diagnostics", {{"before", diagnostics_json(s.before)}, {"after", diagnostics_json(s.after)}}},
          {"run_time_s", s.run_time_s},
          {"stage_times_s", stage_times_json(s.stage_times)}};
}

ExplainSummary explain_summary_from_json(const json& j) {
  ExplainSummary s;
  s.verdict = parse_enum<Verdict>(j.at("verdict").get<std::string>(), "explain.json verdict");
  for (const auto& e : j.at("effects")) s.effects.push_back(effect_of(e));
  for (const auto& d : j.at("demoted")) s.demoted.push_back(demoted_of(d));
  for (const auto& a : j.at("absorbed_alternatives")) s.absorbed_alternatives.push_back(absorbed_of(a));
  for (const auto& u : j.at("unexplained")) s.unexplained.push_back(unexplained_of(u));
  const json& noise = j.at("noise");
  for (const auto& t : noise.at("terms")) {
    NoiseTerm term{t.at("id"), {}};
    for (auto it = t.at("coefficients").begin(); it != t["coefficients"].end(); ++it) term.coefficients.emplace_back(it.key(), it.value().get<double>());
    s.noise.terms.push_back(term);
  }
  s.noise.whitening = NoiseModel::from_json(noise.at("whitening_model"));
  s.noise.floor_dph = noise.at("noise_floor_dph");
  s.fit = fit_of(j.at("fit"));
  s.recording = recording_of(j.at("recording"));
  s.simulation = j.at("simulation");
  s.selection = selection_of(j.at("selection"));
  s.before = diagnostics_of(j.at("diagnostics").at("before"));
  s.after = diagnostics_of(j["diagnostics"].at("after"));
  s.run_time_s = j.at("run_time_s");
  if (j.contains("stage_times_s")) {
    for (const auto& t : j.at("stage_times_s")) s.stage_times.add(t.at("stage").get<std::string>(), t.at("s").get<double>());
  }
  return s;
}

}  // namespace gyrosid
