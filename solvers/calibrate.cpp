#include "solvers/calibrate.h"

#include <algorithm>
#include <functional>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/averaging_bias.h"
#include "model/classical_model.h"
#include "model/greybox_fit.h"
#include "model/held_inputs.h"
#include "solvers/bayes/hybrid_fit.h"
#include "solvers/common/candidates.h"
#include "solvers/solver.h"
#include "solvers/triad/triad_kind.h"

namespace gyrosid {
namespace {

OptionTable classical_table(ClassicalOptions& o) {
  OptionTable t("classical");
  t.integer("bias_order", &o.bias_order, 0, 8, "bias polynomial order in temperature (thesis: 3)")
      .integer("sf_temperature_order", &o.sf_temperature_order, 0, 6, "scale-factor polynomial order in temperature (thesis: 2)")
      .integer("sf_rate_order", &o.sf_rate_order, 0, 10, "scale-factor polynomial order in rate (thesis: 6)")
      .integer("sf_cross_order", &o.sf_cross_order, 0, 4, "temperature order of the rate shape's coefficients, v^i u^k w terms (thesis: 0, separable)");
  return t;
}

struct GreyboxText {
  std::string scale_factor = "surface", temperatures, rates;
};

OptionTable greybox_table(GreyboxOptions& o, GreyboxText& text) {
  OptionTable t("greybox");
  t.integer("bias_order", &o.bias_order, 0, 8, "bias polynomial order in coil temperature")
      .choice("scale_factor", &text.scale_factor, {"surface", "polynomial"}, "scale-factor form")
      .text("surface_temperatures_c", &text.temperatures, "surface grid temperatures, comma-separated (default: thesis grid)")
      .text("surface_rates_dps", &text.rates, "surface grid rates, comma-separated (default: thesis grid)")
      .integer("sf_temperature_order", &o.sf_temperature_order, 0, 6, "polynomial form: order in temperature")
      .integer("sf_rate_order", &o.sf_rate_order, 0, 10, "polynomial form: order in rate")
      .flag("shupe", &o.shupe, "bias proportional to the coil temperature rate")
      .flag("asymmetry", &o.asymmetry, "scale-factor asymmetry between positive and negative rates")
      .flag("g_sensitivity", &o.g_sensitivity, "bias from specific force (needs accel_* columns)")
      .flag("thermal_lag", &o.thermal_lag, "coil temperature lags the probe (first order, tau estimated)")
      .real("lag_max_s", &o.lag_max_s, 1.0, 1e6, "upper bound of the lag search", true)
      .real("ridge", &o.ridge, 0.0, 1.0, "relative ridge on the scaled coefficients");
  return t;
}

nlohmann::json request_json(const CalibrationRequest& r, const std::vector<std::string>& features) {
  return {{"model", r.model}, {"solver", r.model == "rbf" ? r.solver : r.model}, {"options", r.options},
          {"features", features}, {"target", to_string(r.target)}, {"normalization", to_string(r.normalization)}};
}

}  // namespace

void refuse_rbf_fields(const CalibrationRequest& r, bool solver_too) {
  const CalibrationRequest defaults;
  if (solver_too && r.solver != defaults.solver) {
    fail("solver '", r.solver, "' applies to --model rbf and triad; --model ", r.model, " has its own fit (its options: --options-of ", r.model, ")");
  }
  if (r.target != defaults.target) fail("--target ", to_string(r.target), " applies to --model rbf; --model ", r.model, " models the rate error");
  if (r.normalization != defaults.normalization) {
    fail("--normalization ", to_string(r.normalization), " applies to --model rbf; --model ", r.model, " scales its own inputs");
  }
}

namespace {

// A single-gyro model kind fitted to a Dataset of its features.
class DatasetFitter : public GyroModelFitter {
 public:
  using Fit = std::function<std::unique_ptr<CalibrationModel>(const Dataset&, SolveSummary&)>;
  DatasetFitter(std::vector<std::string> features, ModelTarget target, Fit fit)
      : features_(std::move(features)), target_(target), fit_(std::move(fit)) {}
  std::vector<std::string> default_features() const override { return features_; }
  std::unique_ptr<CalibrationModel> fit(const Recording& recording, const std::vector<std::string>& features, SolveSummary& summary) override {
    return fit_(make_dataset(recording, features, target_), summary);
  }

 private:
  std::vector<std::string> features_;
  ModelTarget target_;
  Fit fit_;
};

std::unique_ptr<ModelFitter> classical_fitter(const CalibrationRequest& r) {
  refuse_rbf_fields(r);
  ClassicalOptions o;
  classical_table(o).apply(r.options);
  if (const std::string p = o.validate(); !p.empty()) fail("classical: ", p);
  return std::make_unique<DatasetFitter>(default_features(), ModelTarget::error, [o](const Dataset& d, SolveSummary& s) {
    return std::unique_ptr<CalibrationModel>(fit_classical(d, o, &s));
  });
}

std::unique_ptr<ModelFitter> greybox_fitter(const CalibrationRequest& r) {
  refuse_rbf_fields(r);
  const GreyboxOptions o = greybox_options(r.options);
  return std::make_unique<DatasetFitter>(greybox_features(o), ModelTarget::error, [o, prior = r.greybox_prior](const Dataset& d, SolveSummary& s) {
    if (prior) return std::unique_ptr<CalibrationModel>(estimate_greybox(d, o, prior.get(), &s).model);
    return std::unique_ptr<CalibrationModel>(fit_greybox(d, o, &s));
  });
}

// A network of the measured rate that models the rate error, on a recording that holds the table's rate
// (held_inputs.h): the input then varies by the error alone (m = w + e, w held), and the network would
// interpolate the error as a function of itself - a calibration that returns the table rate in training and
// nothing anywhere else.
void refuse_a_held_rate(const Dataset& d, ModelTarget target) {
  const bool rate_in = std::find(d.features.begin(), d.features.end(), "measured_rate") != d.features.end();
  if (target != ModelTarget::error || !rate_in || d.size() == 0 || !d.reference.allFinite()) return;
  const HeldInputs held = held_inputs(d.reference, Eigen::VectorXd::Zero(d.size()));
  if (!held.rate) return;
  fail("rbf: the recording holds the table rate (within ", format_significant(held.rate_span_dps, 2), " deg/s of ",
       format_significant(held.rate_mean_dps, 3), " deg/s), so the network's measured-rate input varies by the gyro's own "
       "error only and the network would fit the error as a function of itself; calibrate a recording at rest with "
       "--model hybrid or --model classical (the bias over temperature), or record over a range of rates");
}

std::unique_ptr<ModelFitter> rbf_fitter(const CalibrationRequest& r) {
  std::shared_ptr<RbfSolver> solver = make_solver(r.solver, r.options);  // options validated here
  const NormalizationKind normalization = r.normalization;
  const ModelTarget target = r.target;
  return std::make_unique<DatasetFitter>(default_features(), r.target, [solver, normalization, target](const Dataset& d, SolveSummary& s) {
    refuse_a_held_rate(d, target);
    const RbfProblem problem = make_rbf_problem(d, normalization);
    auto net = std::make_unique<RbfNetwork>(problem.empty_network());
    s = train(*solver, problem, *net);
    problem.unscale(*net);
    return std::unique_ptr<CalibrationModel>(std::move(net));
  });
}

class HybridFitter : public GyroModelFitter {
 public:
  explicit HybridFitter(HybridOptions o) : o_(std::move(o)) {}
  std::vector<std::string> default_features() const override { return gyrosid::default_features(); }
  std::unique_ptr<CalibrationModel> fit(const Recording& recording, const std::vector<std::string>& features, SolveSummary& summary) override {
    if (features != gyrosid::default_features()) fail("hybrid: the inputs are measured_rate,temperature");
    return fit_hybrid(recording, o_, summary);
  }

 private:
  HybridOptions o_;
};

std::unique_ptr<ModelFitter> hybrid_fitter(const CalibrationRequest& r) {
  refuse_rbf_fields(r);
  HybridOptions o;
  o.table().apply(r.options);
  if (const std::string p = o.validate(); !p.empty()) fail("hybrid: ", p);
  return std::make_unique<HybridFitter>(std::move(o));
}

}  // namespace

GreyboxOptions greybox_options(const OptionMap& map) {
  GreyboxOptions o;
  GreyboxText text;
  greybox_table(o, text).apply(map);
  o.scale_factor = parse_enum<ScaleFactorForm>(text.scale_factor);
  if (!text.temperatures.empty()) o.surface_temperatures_c = parse_list(text.temperatures, "greybox surface_temperatures_c");
  if (!text.rates.empty()) o.surface_rates_dps = parse_list(text.rates, "greybox surface_rates_dps");
  if (auto p = o.validate(); !p.empty()) fail("greybox: ", p);
  return o;
}

const ModelFitterRegistry& model_fitters() { return extend_model_fitters(); }

ModelFitterRegistry& extend_model_fitters() {
  static ModelFitterRegistry registry = [] {
    ModelFitterRegistry r("model");
    r.add({"rbf", "Gaussian RBF network trained by a named solver (--solver; its options: --options-of <solver>)",
           [] { return "rbf - options are the solver's: see --options-of <solver> (" + rbf_solvers().known() + ")\n"; },
           rbf_fitter})
        .add({"classical", "bias and scale-factor polynomials (thesis s5.3.2)",
              [] {
                ClassicalOptions o;
                return "classical - bias and scale-factor polynomials (thesis s5.3.2):\n" + classical_table(o).help();
              },
              classical_fitter})
        .add({"greybox", "the unified sensor model, coefficients estimated",
              [] {
                GreyboxOptions o;
                GreyboxText t;
                return "greybox - the unified sensor model, coefficients estimated:\n" + greybox_table(o, t).help();
              },
              greybox_fitter})
        .add({"hybrid", "grey-box physics terms plus a Bayesian RBF on what they leave, fitted jointly by the evidence",
              [] {
                HybridOptions o;
                return "hybrid - grey-box physics plus a Bayesian RBF on what it leaves (evidence; posterior covariance):\n" + o.table().help();
              },
              hybrid_fitter})
        .add({"triad", "three gyros: misalignment/scale-factor matrix M, bias b(T), optional G and per-gyro surfaces (thesis eq 3.72)",
              triad_help, triad_fitter});
    return r;
  }();
  return registry;
}

namespace {
std::map<std::string, ModelSample>& plugin_samples() {
  static std::map<std::string, ModelSample> samples;
  return samples;
}
}  // namespace

void register_model_kind(ModelKindPlugin kind) {
  if (!kind.load || !kind.help || !kind.fit || !kind.sample) fail("model kind '", kind.name, "': a plugin needs its loader, help, fitter and sample");
  if (model_kinds().find(kind.name) || model_fitters().find(kind.name)) fail("model kind '", kind.name, "' registered twice");
  extend_model_kinds().add({kind.name, kind.summary, [] { return std::string(); }, std::move(kind.load)});
  extend_model_fitters().add({kind.name, kind.summary, std::move(kind.help), [fit = std::move(kind.fit)](const CalibrationRequest& r) {
                                refuse_rbf_fields(r);
                                return fit(r);
                              }});
  plugin_samples()[kind.name] = std::move(kind.sample);
}

const std::map<std::string, ModelSample>& registered_model_samples() { return plugin_samples(); }

std::string model_help(const std::string& model) { return model_fitters().at(model).help(); }

namespace {

void refuse_a_prior(const CalibrationRequest& r) {
  if (r.greybox_prior && r.model != "greybox") fail("a lot prior (--prior) calibrates the greybox model; --model ", r.model, " takes none");
}

CalibrationResult fit_gyro(GyroModelFitter& fitter, const Recording& recording, const CalibrationRequest& r) {
  CalibrationResult result;
  const std::vector<std::string> features = r.features.empty() ? fitter.default_features() : r.features;
  result.model = fitter.fit(recording, features, result.summary);
  result.training = request_json(r, features);
  if (r.greybox_prior) result.training["prior"] = r.greybox_prior->source;
  // The domain the model was trained on, per input (surface comparisons default to it).
  if (recording.kind() == RecordingKind::single) {
    const Dataset d = make_dataset(recording, result.model->features(), result.model->target());
    nlohmann::json domain = nlohmann::json::object();
    for (Eigen::Index k = 0; k < d.x.cols(); ++k) domain[d.features[static_cast<std::size_t>(k)]] = {d.x.col(k).minCoeff(), d.x.col(k).maxCoeff()};
    result.training["domain"] = domain;
  }
  result.training["recording"] = recording.source();
  result.training["samples"] = recording.rows();
  return result;
}

}  // namespace

ModelFit GyroModelFitter::fit_model(const Recording& recording, const CalibrationRequest& request) {
  return model_fit_of(fit_gyro(*this, recording, request));
}

ModelFit model_fit_of(CalibrationResult result) {
  ModelFit fit;
  fit.extra = {{"training", std::move(result.training)}, {"summary", result.summary}};
  fit.summary = std::move(result.summary);
  fit.model = std::move(result.model);
  return fit;
}

CalibrationResult calibrate(const Recording& recording, const CalibrationRequest& r) {
  refuse_a_prior(r);
  const std::unique_ptr<ModelFitter> fitter = model_fitters().make(r.model, r);
  auto* gyro = dynamic_cast<GyroModelFitter*>(fitter.get());
  if (!gyro) fail("--model ", r.model, " calibrates several gyros together; a single gyro's model is needed here");
  return fit_gyro(*gyro, recording, r);
}

ModelFit fit_model(const Recording& recording, const CalibrationRequest& r) {
  refuse_a_prior(r);
  return model_fitters().make(r.model, r)->fit_model(recording, r);
}

bool fits_one_gyro(const CalibrationRequest& r) {
  return dynamic_cast<const GyroModelFitter*>(model_fitters().make(r.model, r).get()) != nullptr;
}

std::string state_decimation(CalibrationResult& result, const Recording& recording, const Decimation& decimation) {
  const Dataset d = make_dataset(recording, result.model->features(), result.model->target());
  const double rms = units::radps_to_dph(std::sqrt((d.target - result.model->predict(d)).squaredNorm() / static_cast<double>(std::max<Eigen::Index>(d.size(), 1))));
  nlohmann::json summary = decimation_summary(decimation, averaging_bias(*result.model, d, decimation, rms));
  std::string statement = summary.at("statement").get<std::string>();
  result.summary.details["decimation"] = std::move(summary);
  return statement;
}

CalibrationRequest calibration_request_from_config(const ConfigNode& c, const std::vector<std::string>& also_allowed) {
  std::vector<std::string> keys = {"model", "solver", "features", "target", "normalization", "options"};
  keys.insert(keys.end(), also_allowed.begin(), also_allowed.end());
  c.allow_only(keys);
  CalibrationRequest r;
  r.model = c.text("model", r.model);
  r.solver = c.text("solver", r.solver);
  if (c.has("features")) {
    const ConfigNode f = c["features"];
    for (std::size_t i = 0; i < f.size(); ++i) r.features.push_back(f.at(i).as_text());
  }
  if (c.has("target")) r.target = parse_enum<ModelTarget>(c.text("target"), c.where("target"));
  if (c.has("normalization")) r.normalization = parse_enum<NormalizationKind>(c.text("normalization"), c.where("normalization"));
  if (auto opts = c.find("options")) {
    for (const auto& key : opts->keys()) r.options[key] = (*opts)[key].as_text();
  }
  return r;
}

}  // namespace gyrosid
