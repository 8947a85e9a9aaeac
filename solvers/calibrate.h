// Fitting any calibration model to a recording - what `gyrosid calibrate` does, callable in-process by
// experiments: rbf (with a named solver), classical (s5.3.2) or greybox (the unified sensor model).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/decimation.h"
#include "core/recording.h"
#include "core/registry.h"
#include "core/solve_summary.h"
#include "model/calibration_model.h"
#include "model/greybox_fit.h"
#include "model/greybox_prior.h"
#include "model/model_kinds.h"
#include "model/normalizer.h"
#include "solvers/common/options.h"

namespace gyrosid {

struct CalibrationRequest {
  std::string model = "rbf";  // a kind of model_fitters(): rbf | classical | greybox | hybrid | triad | ...
  std::string solver = "ols"; // rbf: its RBF solver; triad: its least-squares back-end (a change of this default)
  OptionMap options;          // solver options (rbf) or the kind's own (classical, greybox, hybrid, triad)
  std::vector<std::string> features;  // empty: the model's defaults
  ModelTarget target = ModelTarget::error;
  NormalizationKind normalization = NormalizationKind::range;
  std::shared_ptr<const GreyboxPrior> greybox_prior;  // greybox: the maximum a posteriori under it (a lot's prior)
};

struct CalibrationResult {
  std::unique_ptr<CalibrationModel> model;
  SolveSummary summary;     // termination, iterations, cost history, time, peak memory; details (nodes, ...)
  nlohmann::json training;  // provenance: recording, samples, request
};

// What fitting any model kind returns (fit_model): the model, the solve, and what its file keeps beside the
// model's values - provenance ("training"), the summary, a fit's own results such as the triad's sigmas and
// observability. save_model(path, *fit.model, fit.extra) writes the file.
struct ModelFit {
  std::unique_ptr<SensorModel> model;
  SolveSummary summary;
  nlohmann::json extra = nlohmann::json::object();
  std::vector<std::string> statement;  // what the fit says beyond its summary, a line each (a triad's estimates)
  std::vector<std::string> warnings;   // what the recording did not do as the fit assumes (a triad hold not still)
};

// Fits one model kind to a recording. Made by the registry from a request, after its options are validated; the
// kind's own options are refused by name when they do not apply to it.
class ModelFitter {
 public:
  virtual ~ModelFitter() = default;
  // `request` is the one the fitter was made from.
  virtual ModelFit fit_model(const Recording& recording, const CalibrationRequest& request) = 0;
};

// A single gyro's kind (rbf, classical, greybox, hybrid, a kind registered from outside): its model is a
// CalibrationModel of the recording's features, the result calibrate() returns.
class GyroModelFitter : public ModelFitter {
 public:
  virtual std::vector<std::string> default_features() const = 0;
  virtual std::unique_ptr<CalibrationModel> fit(const Recording& recording, const std::vector<std::string>& features,
                                                SolveSummary& summary) = 0;
  ModelFit fit_model(const Recording& recording, const CalibrationRequest& request) final;
};

// Every model kind `calibrate` can fit (rbf, classical, greybox, hybrid, triad, ...); help() lists a kind's options.
using ModelFitterRegistry = Registry<ModelFitter, const CalibrationRequest&>;
const ModelFitterRegistry& model_fitters();
// The same registry, open for a program to add the fitter of its own kind (model/model_kinds.h) before it
// fits any (not thread-safe: register at start-up).
ModelFitterRegistry& extend_model_fitters();

// A model kind added from outside the library, whole, by one call (tests/model/toy_model_kind.cpp): its loader
// goes into model_kinds() (model/model_kinds.h), its options' help and its fitter into model_fitters(), its
// sample to the property suites (tests/model/model_samples.h). The built-in kinds sit in those two registries
// themselves: loading a model file is below the solvers (nav, explain and design load models), fitting above.
struct ModelKindPlugin {
  std::string name, summary;
  std::function<std::unique_ptr<SensorModel>(const ModelFile&)> load;        // the model file -> model (a CalibrationModel)
  std::function<std::string()> help;                                          // its options, for --options-of
  std::function<std::unique_ptr<ModelFitter>(const CalibrationRequest&)> fit;  // options validated here
  std::function<std::unique_ptr<CalibrationModel>()> sample;                   // for the property suites
};
void register_model_kind(ModelKindPlugin kind);
// The samples of the kinds registered so, by name: a small instance from planted parameters (no fit).
using ModelSample = std::function<std::unique_ptr<CalibrationModel>()>;
const std::map<std::string, ModelSample>& registered_model_samples();

// The request's solver, target and normalization are the RBF network's; every other kind has its own fit, models
// the rate error and scales its own inputs. Given to one of them they would be dropped without a word - while
// the file's training stated them - so its fitter refuses them by name (`solver_too` false: a kind with a
// solver of its own, the triad's least-squares back-end).
void refuse_rbf_fields(const CalibrationRequest& request, bool solver_too = true);

// A single gyro's model fitted to a recording; a kind of several gyros (the triad) is refused by name.
CalibrationResult calibrate(const Recording& recording, const CalibrationRequest& request);
// Any kind fitted to a recording: a single gyro's as calibrate() fits it, its file's extra the training and summary.
ModelFit fit_model(const Recording& recording, const CalibrationRequest& request);
// A single gyro's fit as any kind's: its file's extra the training and summary.
ModelFit model_fit_of(CalibrationResult result);
// Whether `request`'s kind calibrates one gyro (its options validated on the way; Error naming a bad one).
bool fits_one_gyro(const CalibrationRequest& request);

// The grey-box options of `--set` keys (calibrate --options-of greybox); Error naming a bad key or value.
GreyboxOptions greybox_options(const OptionMap& options);

// A result fitted to block means (core/decimation.h) says so: summary.details["decimation"] holds the
// decimation, the fitted model's averaging bias on `recording` (the block means it was fitted to;
// model/averaging_bias.h) and their "statement", which it returns.
std::string state_decimation(CalibrationResult& result, const Recording& recording, const Decimation& decimation);

class ConfigNode;
// A request from a calibration YAML (keys model, solver, features, target, normalization, options; the
// keys in `also_allowed`, e.g. recording and out for `gyrosid calibrate --config`, pass unread). Unknown
// keys and bad values are errors naming the file, line and key.
CalibrationRequest calibration_request_from_config(const ConfigNode& config, const std::vector<std::string>& also_allowed = {});
std::string model_help(const std::string& model);  // a model kind's options

}  // namespace gyrosid
