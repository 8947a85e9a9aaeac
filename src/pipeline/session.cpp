#include "pipeline/session.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "core/atomic_file.h"
#include "core/checkpoint.h"
#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "design/design.h"
#include "design/sensor_posterior.h"
#include "lot/lot_model.h"
#include "model/calibration_model.h"
#include "pipeline/design_job.h"
#include "pipeline/lot_jobs.h"
#include "report/design_report.h"
#include "sensor/sensor_prior.h"
#include "sim/simulate.h"
#include "core/units.h"
#include "solvers/calibrate.h"
#include "solvers/preset_choice.h"
#include "trajectory/equipment.h"
#include "trajectory/programme.h"

namespace gyrosid {

void SessionOptions::bind(OptionTable& t) {
  t.real("session.min_effective_members", &min_effective_members, 1.0, 1e6, "the posterior's tempering floor: at least this many "
                                                                          "effective members (at most half the prior's)")
      .real("session.drop_share", &drop_share, 0.0, 0.5, "members below this posterior weight are left out of a redesign")
      .flag("session.measured_white_noise", &measured_white_noise, "after each segment the white noise the recording shows replaces "
                                                                   "every member's (their coloured noise stays); default off: measured worse in experiments/adaptive_session");
}

void SessionOptions::set(const OptionMap& options) {
  OptionMap own;
  for (const auto& [key, value] : options) (key.rfind("session.", 0) == 0 ? own : settings)[key] = value;
  OptionTable table("session");
  bind(table);
  table.apply(own);
}

std::string SessionOptions::fingerprint() const {
  std::ostringstream text;
  text << std::setprecision(17) << prior << '\n' << truth << '\n' << budget_min << ' ' << pilot_min << " [";
  for (double u : updates_at_min) text << u << ' ';
  text << "]\n" << model << '\n' << calibration << '\n' << envelope << '\n' << equipment << '\n';
  for (const auto& [key, value] : settings) text << key << '=' << value << '\n';
  text << min_effective_members << ' ' << drop_share << ' ' << measured_white_noise << ' ' << seed;
  return digest(text.str() + file_digests({prior, truth, calibration, equipment}));
}

std::string SessionOptions::validate() const {
  if (prior.empty()) return "--prior is required (a gyrosid-prior/1 file, or a sensor config)";
  if (out.empty()) return "--out DIR is required";
  if (!(budget_min > 0)) return str_cat("--budget-min ", budget_min, " must be positive");
  if (!(pilot_min > 0 && pilot_min < budget_min)) return str_cat("--pilot-min ", pilot_min, " must lie in (0, --budget-min ", budget_min, ")");
  double last = pilot_min;
  for (double u : updates_at_min) {
    if (!(u > last && u < budget_min)) return str_cat("--update-at-min ", u, ": updates must increase after the pilot (", pilot_min, " min) and come before the end (", budget_min, " min)");
    last = u;
  }
  if (!(min_effective_members >= 1.0)) return str_cat("session.min_effective_members ", min_effective_members, " must be at least 1");
  if (!(drop_share >= 0.0 && drop_share < 0.5)) return str_cat("session.drop_share ", drop_share, " must lie in [0, 0.5)");
  return "";
}

std::vector<double> SessionOptions::boundaries_min() const {
  std::vector<double> b{pilot_min};
  b.insert(b.end(), updates_at_min.begin(), updates_at_min.end());
  b.push_back(budget_min);
  return b;
}

namespace {

const GyroSensor& one_gyro(const SensorSpec& spec, const std::string& what) {
  if (const auto* g = std::get_if<GyroSensor>(&spec)) return *g;
  fail(what, " is a triad: a session calibrates one gyro");
}

// What every segment shares: the prior, the envelope and model domain of its members' design contexts, the
// design's settings and the calibration.
struct SessionSetup {
  SensorPrior prior;
  std::optional<SensorSpec> truth;
  design::DesignSettings settings;
  OptionMap solver_options;
  std::string model;  // --model, auto resolved (design_model)
  design::ModelFamily family = design::ModelFamily::rbf;
  std::shared_ptr<const design::Envelope> envelope;
  design::Domain domain;
  std::string calibration_text, calibration_source;
  CalibrationRequest calibration;
  bool lot_prior = false;  // a lot as --prior with the greybox model: its structure, and its population as the calibrations' prior
  std::string lot_note;    // what take_lot decided
};

void prepare(const SessionOptions& o, SessionSetup& s) {
  s.prior = load_sensor_prior(o.prior);
  for (const auto& m : s.prior.members) one_gyro(m.sensor, str_cat("prior member '", m.name, "' (", m.origin, ")"));
  if (!o.truth.empty()) s.truth = load_sensor_file(o.truth), one_gyro(*s.truth, "--truth " + o.truth);
  s.settings.space.take(load_equipment(o.equipment));
  s.solver_options = s.settings.apply(o.settings);
  design::make_design_solver("nlopt", s.solver_options, o.seed);  // bad options fail before any work
  const std::optional<LotModel> lot = load_lot_if_learned(o.prior);
  std::ostringstream model_note;  // design's log line; session.json records the model itself
  s.model = design_model(o.model, lot, model_note);
  s.family = parse_enum<design::ModelFamily>(s.model, "--model");
  if (lot) {
    std::ostringstream note;
    s.lot_prior = take_lot(o.prior, *lot, s.model, s.family, o.settings, true, s.settings.model, note);
    s.lot_note = note.str();
    if (s.lot_prior && !o.calibration.empty()) {
      fail("--calibration: with the lot ", o.prior, " as --prior and --model greybox the calibration is the lot's (its grey-box structure under its population, calibrate --prior)");
    }
  }
  s.settings.envelope.flights = split_list(o.envelope);
  s.envelope = std::make_shared<const design::Envelope>(design::load_envelope(s.settings.envelope, as_triad(s.prior.members.front().sensor)));
  s.settings.space.budget_min = o.budget_min;
  s.domain = design::model_domain(design::design_space(*s.envelope, s.settings.space));
  if (o.calibration.empty()) {
    const design::NoiseSpec noise = design::NoiseSpec::of(std::get<GyroSensor>(s.prior.members.front().sensor).noise);
    s.calibration_text = design::calibration_yaml(s.family, s.settings.model, s.domain, noise);
    s.calibration_source = (o.out / "calibration.yaml").string();
  } else {
    s.calibration_text = config_text(o.calibration);
    s.calibration_source = o.calibration;
  }
  s.calibration = calibration_request_from_config(o.calibration.empty() ? ConfigNode::parse(s.calibration_text, s.calibration_source)
                                                                        : ConfigNode::load(o.calibration));
  if (s.lot_prior) take_lot_prior(s.calibration, *lot);
}

// Per flight, over the members with weight: the weighted mean, least and largest predicted criterion of fit.
nlohmann::json band_json(const std::vector<design::Prediction>& predictions, const std::vector<double>& weights) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t f = 0; f < predictions.front().flights.size(); ++f) {
    double mean = 0.0, lo = INFINITY, hi = 0.0, total = 0.0;
    for (std::size_t m = 0; m < predictions.size(); ++m) {
      const double c = predictions[m].flights[f].cof_m;
      mean += weights[m] * c, total += weights[m], lo = std::min(lo, c), hi = std::max(hi, c);
    }
    j[predictions.front().flights[f].flight] = {{"cof_mean_m", mean / total}, {"cof_min_m", lo}, {"cof_max_m", hi}};
  }
  return j;
}

// Rows [first, rows) of a recording, the time counted from the first of them.
Recording tail_rows(const Recording& r, std::size_t first, const std::string& source) {
  Recording out(source);
  for (const auto& [key, value] : r.metadata()) out.set_meta(key, value);
  const double t0 = r.column("t_s")[first];
  for (const auto& name : r.names()) {
    std::vector<double> v(r.column(name).begin() + static_cast<std::ptrdiff_t>(first), r.column(name).end());
    if (name == "t_s") std::for_each(v.begin(), v.end(), [&](double& t) { t -= t0; });
    out.set_column(name, std::move(v));
  }
  return out;
}

// One recording of the session: the segments' rows in order, each segment's time shifted by its start.
Recording joined(const std::vector<Recording>& segments, const std::vector<double>& start_s) {
  Recording all("<session recording>");
  for (const auto& [key, value] : segments.front().metadata()) all.set_meta(key, value);
  all.set_meta("description", str_cat("gyrosid session: ", segments.size(), " segments"));
  for (const auto& name : segments.front().names()) {
    std::vector<double> v;
    for (std::size_t k = 0; k < segments.size(); ++k) {
      if (!segments[k].has(name)) fail(segments[k].source(), ": no column ", name, " (segment 1 has it; the segments must record the same columns)");
      for (double x : segments[k].column(name)) v.push_back(name == "t_s" ? x + start_s[k] : x);
    }
    all.set_column(name, std::move(v));
  }
  return all;
}

class SessionRun {
 public:
  SessionRun(const SessionOptions& o, const SessionSetup& s, std::string fingerprint) : o_(o), s_(s), fingerprint_(std::move(fingerprint)) {
    for (const auto& m : s_.prior.members) {
      weights_.push_back(m.weight / s_.prior.total_weight());
      sensors_.push_back(std::get<GyroSensor>(m.sensor));
    }
    contexts_.resize(sensors_.size());
    boundaries_ = o_.boundaries_min();
    checkpoint_ = checkpoint_in(o_.out, "session", fingerprint_, o_.resume);
    if (o_.resume) {  // a killed write's temporaries in the segments' folders too
      for (std::size_t k = 0; k < boundaries_.size(); ++k) remove_stale_temporaries(o_.out / segment_dir(k));
    }
    json_ = {{"format", "gyrosid-session/1"},
             {"prior", {{"file", o_.prior}, {"name", s_.prior.name}, {"members", members_json(weights_)}}},
             {"truth", o_.truth}, {"budget_min", o_.budget_min}, {"seed", o_.seed}, {"model", s_.model},
             {"calibration", s_.calibration_source}, {"fingerprint", fingerprint_}, {"segments", nlohmann::json::array()}};
    if (!s_.lot_note.empty()) json_["prior"]["lot"] = s_.lot_note.substr(0, s_.lot_note.size() - 1);  // what take_lot decided
    if (s_.lot_prior) json_["prior"]["calibration_prior"] = o_.prior;  // every calibration is calibrate --prior with the lot
  }

  SessionResult run() {
    SessionResult result;
    result.segments = static_cast<int>(boundaries_.size());
    for (std::size_t k = 0; k < boundaries_.size(); ++k) {
      design_segment(k);
      const auto recording = o_.out / segment_dir(k) / "recording.csv";
      if (!record_segment(k, recording)) {
        result.waiting_for = recording;
        json_["status"] = str_cat("waiting for ", recording.string());
        write_file_atomic(o_.out / "session.json", json_.dump(2) + "\n");
        result.session = json_;
        return result;
      }
      update(k);
      result.segments_done = static_cast<int>(k) + 1;
    }
    finish();
    result.model = o_.out / "model.json";
    result.session = json_;
    return result;
  }

 private:
  static std::string segment_dir(std::size_t k) { return str_cat("segment_", k + 1); }
  double start_min(std::size_t k) const { return k == 0 ? 0.0 : boundaries_[k - 1]; }
  void step(const std::string& what) const {
    if (o_.on_step) o_.on_step(what);
  }

  nlohmann::json members_json(const std::vector<double>& w) const {
    nlohmann::json j = nlohmann::json::array();
    for (std::size_t m = 0; m < w.size(); ++m) j.push_back({{"name", s_.prior.members[m].name}, {"weight", w[m]}});
    return j;
  }

  // The members a design is for: those holding at least drop_share of the current weight.
  std::vector<std::size_t> active() const {
    std::vector<std::size_t> a;
    const double top = *std::max_element(weights_.begin(), weights_.end());
    for (std::size_t m = 0; m < weights_.size(); ++m) {
      if (weights_[m] >= o_.drop_share || weights_[m] == top) a.push_back(m);
    }
    return a;
  }

  // Member m's design context, for its sensor as the session now knows it (built when first needed).
  const design::DesignContext& context(std::size_t m) {
    if (!contexts_[m]) {
      step(str_cat("session: the design context of member ", m + 1, "/", sensors_.size()));
      contexts_[m] = std::make_unique<design::DesignContext>(sensors_[m], s_.envelope, s_.family, s_.settings.model, design::Criterion::cof, s_.domain);
    }
    return *contexts_[m];
  }

  // The white noise the recording shows (5th differences of the rate error, solvers/preset_choice.h: robust to
  // the error surface) in place of every member's own: an empirical-Bayes step - a pilot's thousands of samples
  // identify it to a few per cent, far better than any member's guess - after which the members differ by their
  // error laws and coloured noise only.
  nlohmann::json measure_white_noise(const Recording& all) {
    const double sigma_dph = choose_preset(all).noise_sigma_dph;
    const double arw = units::dph_to_radps(sigma_dph) * std::sqrt(median_sample_interval(all.column("t_s")));
    for (std::size_t m = 0; m < sensors_.size(); ++m) {
      sensors_[m].noise.arw_rad_rt_s = arw;
      contexts_[m].reset();
    }
    return {{"white_dph_per_sample", sigma_dph}, {"arw_dph_rt_h", units::radps_to_dph(arw) / 60.0}};
  }

  TrajectorySpec spec_of(const TableProfile& profile) const {
    TrajectorySpec t;
    t.profile = profile;
    t.sampling.rate_hz = s_.settings.space.rate_hz;
    return t;
  }

  // The segment's programme: designed for the current weights as the continuation of the recorded ones, or taken
  // from a resumed session's file. Its record in session.json says what it was designed for and predicted.
  void design_segment(std::size_t k) {
    const auto dir = o_.out / segment_dir(k);
    const auto file = dir / "trajectory.yaml";
    const std::string key = str_cat("segment_", k + 1);
    nlohmann::json record = checkpoint_.record(key);
    if (record.is_null() || !std::filesystem::exists(file)) {
      const std::vector<std::size_t> members = active();
      const double minutes = boundaries_[k] - start_min(k);
      step(str_cat("session: segment ", k + 1, "/", boundaries_.size(), ": designing ", format_significant(minutes, 4), " min for ",
                   members.size(), " of ", weights_.size(), " members"));
      std::vector<design::WeightedContext> contexts;
      std::vector<double> w;
      for (std::size_t m : members) contexts.push_back({&context(m), weights_[m]}), w.push_back(weights_[m]);
      design::DesignRequest request;
      request.space = s_.settings.space;
      request.space.budget_min = minutes;
      request.quadrature = s_.settings.quadrature;
      request.prior = s_.settings.prior;
      request.solver_options = s_.solver_options;
      request.seed = o_.seed;
      request.recorded = recorded_;
      std::filesystem::create_directories(dir);
      Checkpoint stages = checkpoint_in(dir, "design", str_cat(fingerprint_, "/", key), o_.resume);
      request.checkpoint = &stages;
      design::DesignResult r = design::design_trajectory(contexts, request);
      r.trajectory.profile.name = str_cat("session segment ", k + 1);
      std::vector<design::Prediction> predicted = r.member_predictions.empty() ? std::vector<design::Prediction>{r.predicted} : r.member_predictions;
      nlohmann::json designed_for = nlohmann::json::array();
      for (std::size_t i = 0; i < members.size(); ++i) designed_for.push_back({{"name", s_.prior.members[members[i]].name}, {"weight", w[i]}});
      record = {{"segment", k + 1}, {"start_min", start_min(k)}, {"duration_min", minutes}, {"trajectory", (segment_dir(k) + "/trajectory.yaml")},
                {"designed_for", designed_for}, {"predicted_before", band_json(predicted, w)},
                {"design", {{"evaluations", r.summary.evaluations}, {"time_s", r.summary.time_s}, {"objective", r.summary.final_cost}}}};
      write_designed_programme(dir, r.trajectory, design_json(r, {{"session", o_.out.string()}, {"segment", k + 1}}));
      stages.finish();
      checkpoint_.save_record(key, record);
    }
    json_["segments"].push_back(record);
    // Always the file's programme, so that a fresh and a resumed session continue from the same numbers.
    recorded_ = concatenate(recorded_, load_trajectory_file(file.string()).profile);
  }

  // The segment's recording: the lab's file, or the truth simulated on the programme so far and cut at the
  // segment's start. False when the lab has yet to record it.
  bool record_segment(std::size_t k, const std::filesystem::path& file) {
    const double start_s = start_min(k) * 60.0;
    if (std::filesystem::exists(file) && (o_.resume || !s_.truth)) {
      Recording r = read_recording(file);
      for (const char* c : {"t_s", "ref_rate_dps", "gyro_dps"}) require_column(r, c, "a session calibrates one gyro");
      segments_.push_back(std::move(r));
    } else if (s_.truth) {
      step(str_cat("session: segment ", k + 1, ": simulating the true sensor"));
      const Simulation sim = simulate(*s_.truth, spec_of(recorded_), o_.seed);
      const std::vector<double>& t = sim.recording.column("t_s");
      const auto first = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), start_s - 1e-6) - t.begin());
      segments_.push_back(tail_rows(sim.recording, first, file.string()));
      write_recording(segments_.back(), file);
    } else {
      return false;
    }
    starts_s_.push_back(start_s);
    return true;
  }

  // The posterior after segment k: every member's likelihood of all that is recorded, tempered; the programme so
  // far predicted on it; an interim calibration (but after the last segment: the final one follows).
  void update(std::size_t k) {
    step(str_cat("session: segment ", k + 1, ": updating the prior by the recording (", weights_.size(), " members)"));
    all_ = joined(segments_, starts_s_);
    const Recording& all = all_;
    nlohmann::json& seg = json_["segments"].back();
    if (o_.measured_white_noise) seg["measured_noise"] = measure_white_noise(all);
    std::vector<double> log_l;
    for (const auto& g : sensors_) log_l.push_back(design::recording_log_likelihood(g, recorded_, all.column("t_s"), all.column("gyro_dps")));
    std::vector<double> prior_w;
    for (const auto& m : s_.prior.members) prior_w.push_back(m.weight);
    const design::SensorPosterior post = design::tempered_posterior(prior_w, log_l, o_.min_effective_members);
    weights_ = post.weights;
    std::vector<design::Prediction> predicted;
    std::vector<double> w;
    for (std::size_t m : active()) predicted.push_back(design::evaluate_trajectory(context(m), spec_of(recorded_))), w.push_back(weights_[m]);
    seg["recording"] = segment_dir(k) + "/recording.csv";
    seg["samples"] = segments_.back().rows();
    seg["posterior"] = {{"learning_rate", post.learning_rate}, {"effective_members", post.effective_members}, {"members", members_json(weights_)}};
    for (std::size_t m = 0; m < log_l.size(); ++m) seg["posterior"]["members"][m]["log_likelihood"] = log_l[m];
    seg["predicted_after"] = band_json(predicted, w);
    if (k + 1 < boundaries_.size()) {
      step(str_cat("session: segment ", k + 1, ": interim calibration on ", all.rows(), " samples"));
      const CalibrationResult fit = calibrate(all, s_.calibration);
      save_model(o_.out / segment_dir(k) / "model.json", *fit.model, {{"training", fit.training}, {"summary", fit.summary}});
      seg["interim_model"] = segment_dir(k) + "/model.json";
    }
  }

  void finish() {
    const Recording& all = all_;  // the last update's
    step(str_cat("session: the final calibration on ", all.rows(), " samples"));
    write_recording(all, o_.out / "recording.csv");
    write_file_atomic(o_.out / "trajectory.yaml", programme_yaml(spec_of(recorded_)));
    const CalibrationResult fit = calibrate(all, s_.calibration);
    save_model(o_.out / "model.json", *fit.model, {{"training", fit.training}, {"summary", fit.summary}});
    json_["status"] = "complete";
    json_["final"] = {{"model", "model.json"}, {"recording", "recording.csv"}, {"trajectory", "trajectory.yaml"}, {"samples", all.rows()},
                      {"predicted", json_["segments"].back()["predicted_after"]}, {"calibration", {{"termination", to_string(fit.summary.termination)},
                                                                                                     {"time_s", fit.summary.time_s}}}};
    write_file_atomic(o_.out / "session.json", json_.dump(2) + "\n");
    checkpoint_.finish();
  }

  const SessionOptions& o_;
  const SessionSetup& s_;
  const std::string fingerprint_;
  Checkpoint checkpoint_;
  nlohmann::json json_;
  std::vector<double> weights_, boundaries_, starts_s_;
  std::vector<GyroSensor> sensors_;  // the members, with the measured white noise once it is known
  std::vector<std::unique_ptr<design::DesignContext>> contexts_;
  TableProfile recorded_;
  std::vector<Recording> segments_;
  Recording all_;  // the segments joined, as of the last update
};

}  // namespace

SessionResult run_session(const SessionOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail(p);
  const std::string fingerprint = o.fingerprint();
  if (std::filesystem::exists(o.out / "session.json")) {
    if (!o.resume) fail(o.out.string(), " holds a session (session.json): continue it with --resume, or choose another --out");
    const nlohmann::json j = nlohmann::json::parse(config_text((o.out / "session.json").string()), nullptr, false);
    if (!j.is_object() || j.value("fingerprint", "") != fingerprint) {
      fail(o.out.string(), "/session.json: the session there was started with other inputs, options or seed (another fingerprint); "
           "--resume continues a session with the same ones");
    }
    if (j.value("status", "") == "complete") {
      const int n = static_cast<int>(j["segments"].size());
      return {n, n, std::nullopt, o.out / "model.json", j};
    }
  }
  std::filesystem::create_directories(o.out);
  SessionSetup setup;
  prepare(o, setup);
  if (o.calibration.empty()) write_file_atomic(o.out / "calibration.yaml", setup.calibration_text);
  return SessionRun(o, setup, fingerprint).run();
}

}  // namespace gyrosid
