// `gyrosid design` as a job (issue 31): the CLI and the Python bindings both call it. prepare_design() reads
// and checks the inputs as the command line gives them, builds the design context (the sensor or the first
// member of a prior, the envelope, the model over the design space's domain) and predicts the reference
// (cof_minimax, --reference) and the compared or evaluated trajectories; run_design_job() then designs over
// every member of the prior. Writing the files is the caller's (report/design_report.h holds their content).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/builtin_configs.h"
#include "core/checkpoint.h"
#include "design/design.h"
#include "lot/lot_model.h"
#include "report/design_report.h"
#include "sensor/sensor_prior.h"

namespace gyrosid {

inline constexpr const char* kDefaultEquipment = "builtin:equipment/thesis_lab.yaml";

// The inputs, named as `gyrosid design`'s options (its --help teaches them).
struct DesignJobInput {
  double budget_min = 0.0;  // required unless evaluating
  std::string model = "auto", envelope = "short,medium,long", uniform_domain = "-20,60,100", criterion;  // model: DesignSetup::model
  std::string sensor = kDefaultSensor, solver = "nlopt", reference, reference_model;
  std::string prior;  // a prior over sensors (sensor/sensor_prior.h) in place of `sensor`
  std::string equipment = kDefaultEquipment;
  std::string noise;  // an allan.json whose identified model replaces the sensor config's noise
  std::string reference_statistic = "auto";
  std::vector<std::string> set, evaluate, compare{kDefaultTrajectory};
  std::uint64_t seed = 1;
  bool without_lot_prior = false;  // a lot as prior: its members only, each unit calibrated by its own data
  std::string invocation;          // how it was called, for the report and the provenance
};

// What the command line sets before a sensor is read: the design's settings (--set over the equipment's), the
// envelope, the criterion and model family, and whether a lot's population is the calibration's prior. Every
// option is checked here, before any prediction.
struct DesignSetup {
  design::DesignSettings settings;
  OptionMap solver_options;
  design::Criterion criterion{};
  std::string model;  // --model, or for auto the model `gyrosid calibrate` fits on the recording (design_model)
  design::ModelFamily family{};
  bool lot = false;        // --prior is a lot (gyrosid lot learn)
  bool lot_prior = false;  // ... whose population the calibration designed for fits with
  std::optional<design::ReferenceStatistic> fixed_statistic;  // --reference-statistic, none for auto
};

// `--model auto` (design and session): the model `gyrosid calibrate` fits on the recording a design gives - the
// greybox under a lot whose structure a grey-box design takes, else the hybrid (said in `log`); any other name as it is.
std::string design_model(const std::string& model_option, const std::optional<LotModel>& lot, std::ostream& log);

// A lot (`gyrosid lot learn`) as the prior of a design or session with the grey-box model: the design's model
// takes the lot's structure and, with `calibration_prior`, the calibration it designs for fits with the lot's
// population as its prior (`calibrate --prior`), so the predicted accuracy counts what the earlier units
// taught. Returns whether it does. With another family only the lot's members count (said in `log`). Error for
// a --set that would change the structure, or a structure the design's grey-box model has not.
bool take_lot(const std::string& lot_file, const LotModel& lot, const std::string& model_name, design::ModelFamily family, const OptionMap& options,
              bool calibration_prior, design::ModelOptions& model, std::ostream& log);

struct PreparedDesign {
  DesignSetup setup;
  SensorPrior prior;
  std::shared_ptr<const design::Envelope> envelope;
  std::unique_ptr<design::DesignContext> context;  // the nominal sensor's (the prior's first member)
  DesignReportInput report;                        // the reference first, then the compared or evaluated
  nlohmann::json provenance;
};

// Every input checked (Error naming the option) before any prediction; what is decided on the way (a lot's
// structure taken, a measured noise in place of the configs') is said on `log`.
PreparedDesign prepare_design(const DesignJobInput& input, std::ostream& log);

struct DesignJobResult {
  design::DesignResult result;
  std::vector<PriorMemberPredictions> members;  // the design and the compared on each member of a prior of more than one
  nlohmann::json design_file;                    // design.json's content
};

// The design over the prepared prior's members; `checkpoint` (may be null) keeps the finished stages so a
// killed design resumes to the same result.
DesignJobResult run_design_job(const PreparedDesign& prepared, const DesignJobInput& input, Checkpoint* checkpoint);

}  // namespace gyrosid
