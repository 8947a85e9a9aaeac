// gyrosid design: optimise a calibration trajectory for a time budget, or state the predicted accuracy of
// existing trajectories (--evaluate).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <utility>

#include "cli/app.h"
#include "cli/common.h"
#include "cli/resume.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "design/design.h"
#include "design/design_solver.h"
#include "lot/lot_model.h"
#include "noise/composite.h"
#include "noise/processes.h"
#include "report/allan_report.h"
#include "report/design_report.h"
#include "sensor/sensor_config.h"
#include "sensor/sensor_prior.h"
#include "trajectory/equipment.h"
#include "trajectory/programme.h"

namespace gyrosid::cli {
namespace {

constexpr const char* kDefaultEquipment = "builtin:equipment/thesis_lab.yaml";

struct DesignCommand {
  double budget_min = 0.0;
  std::string model = "rbf", envelope = "short,medium,long", uniform_domain = "-20,60,100", criterion;
  std::string sensor = kDefaultSensor, solver = "nlopt", out, options_of, reference, reference_model;
  std::string prior;  // a prior over sensors (sensor/sensor_prior.h) in place of --sensor
  std::string equipment = kDefaultEquipment;
  std::string noise;  // an allan.json whose identified model replaces the sensor config's noise
  std::string reference_statistic = "auto";
  std::vector<std::string> set, evaluate, compare{"builtin:trajectories/dual_scan.yaml"};
  std::uint64_t seed = 1;
  bool resume = false;
  bool without_lot_prior = false;  // a lot as --prior: its members only, each unit calibrated by its own data
  const CLI::App* command = nullptr;  // the parsed subcommand, for the checkpoint's fingerprint

  std::string command_line() const {
    std::string out = evaluate.empty() ? str_cat("gyrosid design --budget-min ", format_number(budget_min)) : "gyrosid design --evaluate";
    for (const auto& e : evaluate) out += " " + e;
    out += str_cat(" --model ", model, " --envelope ", envelope, prior.empty() ? " --sensor " + sensor : " --prior " + prior);
    if (without_lot_prior) out += " --without-lot-prior";
    if (!noise.empty()) out += " --noise " + noise;
    if (equipment != kDefaultEquipment) out += " --equipment " + equipment;
    if (evaluate.empty()) out += str_cat(" --solver ", solver, " --seed ", seed);
    if (!criterion.empty()) out += " --criterion " + criterion;
    if (!reference.empty()) out += str_cat(" --reference ", reference, reference_model.empty() ? "" : " --reference-model " + reference_model,
                                           " --reference-statistic ", reference_statistic);
    for (const auto& kv : set) out += " --set " + kv;
    return out;
  }
};

std::string describe(const design::Prediction& p) {
  std::string out;
  for (const auto& f : p.flights) {
    out += str_cat(out.empty() ? "" : ", ", f.flight, " ", format_significant(f.cof_m, 3), " m (",
                   format_significant(f.surface_rms_dph, 3), " deg/h)");
  }
  if (p.uniform_surface_rms_dph) out += str_cat(out.empty() ? "" : ", ", "uniform ", format_significant(*p.uniform_surface_rms_dph, 3), " deg/h");
  return out;
}

// --options-of: the options of a design solver or of the design itself.
void print_options_of(const std::string& name) {
  if (name == "design") {
    design::DesignSettings s;
    std::cout << "design options (--set key=value):\n" << s.table().help();
  } else {
    std::cout << design::design_solvers().at(name).help();
  }
}

// --evaluate: the predicted accuracy of each trajectory, printed and (with --out) written.
void write_evaluation(const DesignCommand& c, const design::DesignContext& context, const DesignReportInput& report,
                      const nlohmann::json& provenance) {
  const std::filesystem::path dir = c.out;
  nlohmann::json j = {{"format", "gyrosid-design-evaluation/1"}, {"provenance", provenance}, {"trajectories", nlohmann::json::object()}};
  // A --reference (cof_minimax) comes first in report.compared, before the evaluated trajectories.
  const std::size_t first = report.compared.size() - c.evaluate.size();
  for (std::size_t i = 0; i < report.compared.size(); ++i) {
    const auto& [name, p] = report.compared[i];
    std::cout << name << " (" << format_significant(p.duration_min, 4) << " min): predicted " << describe(p) << "\n";
    if (i >= first) j["trajectories"][c.evaluate[i - first]] = prediction_json(p);
  }
  if (!c.out.empty()) {
    write_file_atomic(dir / "evaluation.json", j.dump(2) + "\n");
    write_file_atomic(dir / "report.md", design_report_markdown(report));
    const TrajectorySpec first = load_trajectory_file(c.evaluate.front());
    plot_design_coverage(dir / "coverage.png", design::observe_trajectory(context, first), context.envelope(),
                         first.profile.name + ": samples over the envelope");
    std::cout << "wrote " << c.out << "/evaluation.json, report.md, coverage.png\n";
  }
}

// The prior (--prior) or the one sensor (--sensor), every member's gyro noise replaced by an identified model
// when --noise names an allan.json (noise/identify.h: the noise a real recording showed, in place of the
// configs' assumption).
SensorPrior prior_with_measured_noise(const DesignCommand& c) {
  SensorPrior prior = load_sensor_prior(c.prior.empty() ? c.sensor : c.prior);
  if (c.noise.empty()) return prior;
  std::string left_out;
  const NoiseOptions noise = noise_options_of(load_identified_noise(c.noise).scaled(units::dph_to_radps(1.0)), &left_out);
  if (auto problem = noise.validate(); !problem.empty()) fail(c.noise, ": ", problem);
  std::cout << "noise: " << c.noise << " in place of " << prior.source << "'s" << (left_out.empty() ? "" : " (without " + left_out + ")") << "\n";
  for (auto& m : prior.members) m.sensor = with_gyro_noise(m.sensor, noise);
  return prior;
}

// A lot (`gyrosid lot learn`) as --prior with the grey-box model: the design's model takes the lot's structure
// and, unless --without-lot-prior, the calibration it designs for fits with the lot's population as its prior
// (`calibrate --prior`), so the predicted accuracy counts what the earlier units taught. Returns whether it does.
bool take_lot(const DesignCommand& c, const LotModel& lot, design::ModelFamily family, const OptionMap& options, design::ModelOptions& model) {
  if (family != design::ModelFamily::greybox) {
    std::cout << "prior: " << c.prior << " is a lot; its structure and population are the greybox model's, so with --model " << c.model
              << " the design takes its members only\n";
    return false;
  }
  const GreyboxOptions& s = lot.structure;
  for (const char* key : {"model.bias_order", "model.grid_temperatures", "model.grid_temperatures_c", "model.grid_rates_dps", "model.shupe", "model.thermal_lag"}) {
    if (options.count(key)) fail("--set ", key, ": the lot ", c.prior, " fixes the grey-box structure");
  }
  if (s.scale_factor != ScaleFactorForm::surface || s.asymmetry || s.g_sensitivity) {
    fail("--prior ", c.prior, ": the lot's grey-box structure has ", s.asymmetry ? "asymmetry" : s.g_sensitivity ? "g-sensitivity" : "a polynomial scale factor",
         ", which the design's grey-box model has not (--model rbf, classical or hybrid design for its members alone)");
  }
  model.bias_order = s.bias_order;
  model.grid_temperatures_c = format_numbers(s.surface_temperatures_c, ",");
  model.grid_rates_dps = format_numbers(s.surface_rates_dps, ",");
  model.shupe = s.shupe;
  model.thermal_lag = s.thermal_lag;
  std::cout << "prior: the lot " << c.prior << " (" << lot.unit_names.size() << " units): its grey-box structure";
  if (c.without_lot_prior) {
    std::cout << ", each unit calibrated by its own data (--without-lot-prior)\n";
    return false;
  }
  model.calibration_prior = std::make_shared<const GreyboxPrior>(lot.prior());
  std::cout << ", and its population as the calibration's prior (calibrate --prior)\n";
  return true;
}

// A design for a prior of more than one sensor: every member's context beside the nominal one (the first's,
// built by the caller), with the same envelope, model, criterion and domain.
struct PriorContexts {
  std::vector<std::unique_ptr<design::DesignContext>> owned;  // members 1.. (member 0 is the nominal context)
  std::vector<design::WeightedContext> members;
};

PriorContexts prior_contexts(const SensorPrior& prior, const design::DesignContext& nominal, std::shared_ptr<const design::Envelope> envelope,
                             const design::ModelOptions& model) {
  PriorContexts p;
  p.members.push_back({&nominal, prior.members.front().weight});
  for (std::size_t k = 1; k < prior.members.size(); ++k) {
    p.owned.push_back(std::make_unique<design::DesignContext>(prior.members[k].sensor, envelope, nominal.family(), model, nominal.criterion(), nominal.model_domain()));
    p.members.push_back({p.owned.back().get(), prior.members[k].weight});
  }
  return p;
}

// The design and the compared trajectories predicted on every member of the prior.
std::vector<PriorMemberPredictions> prior_predictions(const SensorPrior& prior, const PriorContexts& contexts, const design::DesignResult& r,
                                                      const std::vector<std::string>& compare) {
  std::vector<TrajectorySpec> compared;
  for (const auto& path : compare) compared.push_back(load_trajectory_file(path));
  std::vector<PriorMemberPredictions> out;
  for (std::size_t k = 0; k < prior.members.size(); ++k) {
    PriorMemberPredictions m{prior.members[k].name, prior.members[k].origin, prior.members[k].weight, r.member_predictions[k], {}};
    for (const auto& spec : compared) m.compared.emplace_back(spec.profile.name, design::evaluate_trajectory(*contexts.members[k].context, spec));
    out.push_back(std::move(m));
  }
  return out;
}

// What the command line sets before a sensor is read: the design's settings (--set over the equipment's), the
// envelope, the criterion and model family, and whether a lot's population is the calibration's prior. Every
// option is checked here, before any prediction.
struct DesignSetup {
  design::DesignSettings settings;
  OptionMap solver_options;
  design::Criterion criterion{};
  design::ModelFamily family{};
  bool lot = false;        // --prior is a lot (gyrosid lot learn)
  bool lot_prior = false;  // ... whose population the calibration designed for fits with
  std::optional<design::ReferenceStatistic> fixed_statistic;  // --reference-statistic, none for auto
};

void set_envelope(const DesignCommand& c, design::EnvelopeOptions& envelope) {
  const auto names = split_list(c.envelope);
  if (names.size() != 1 || names.front() != "uniform") {
    envelope.flights = names;
    return;
  }
  envelope.uniform = true;
  envelope.flights.clear();
  const auto d = split_list(c.uniform_domain);
  if (d.size() != 3) fail("--uniform-domain: expected T_MIN_C,T_MAX_C,RATE_DPS, got '", c.uniform_domain, "'");
  envelope.uniform_domain.temp_min_c = std::stod(d[0]);
  envelope.uniform_domain.temp_max_c = std::stod(d[1]);
  envelope.uniform_domain.rate_max_radps = units::dps_to_radps(std::stod(d[2]));
}

DesignSetup design_setup(const DesignCommand& c) {
  DesignSetup s;
  OptionMap options;
  for (const auto& kv : c.set) {
    const auto [key, value] = split_option(kv);
    options[key] = value;
  }
  s.settings.space.take(load_equipment(c.equipment));  // what the hardware can do; --set space.* overrides it
  s.solver_options = s.settings.apply(options);
  set_envelope(c, s.settings.envelope);
  s.criterion = c.criterion.empty() ? (s.settings.envelope.uniform ? design::Criterion::surface : design::Criterion::cof)
                                    : parse_enum<design::Criterion>(c.criterion, "--criterion");
  if (s.criterion == design::Criterion::cof_minimax) s.settings.minimax_defaults(options);  // it always has a reference (below)
  s.family = parse_enum<design::ModelFamily>(c.model, "--model");
  const std::optional<LotModel> lot = c.prior.empty() ? std::nullopt : load_lot_if_learned(c.prior);
  s.lot = lot.has_value();
  if (c.without_lot_prior && !s.lot) fail("--without-lot-prior is for a lot (gyrosid lot learn) as --prior");
  s.lot_prior = s.lot && take_lot(c, *lot, s.family, options, s.settings.model);
  design::ModelOptions& model = s.settings.model;
  if (s.criterion == design::Criterion::effects && !model.shupe && !model.hysteresis && !model.thermal_lag) {
    model.shupe = model.hysteresis = model.thermal_lag = true;  // what the criterion separates
  }
  const bool evaluating = !c.evaluate.empty();
  if (!evaluating && !(c.budget_min > 0)) fail("--budget-min is required (a positive number of minutes) unless --evaluate is given");
  if (!evaluating && c.out.empty()) fail("--out DIR is required for a design");
  if (!evaluating) design::make_design_solver(c.solver, s.solver_options, c.seed);  // bad options fail before any work
  // The exact selection's options, before any prediction (cof_minimax always gets its reference below).
  if (auto p = s.settings.selection.validate(s.criterion, true); !p.empty()) fail("design: ", p);
  // auto: mse for a reference of the same model, else the reference's cof (assessment.h). mse was measured worse
  // than posterior against the dual scan with the fixed dictionary's prior (2026-11-24); every design since the
  // evidence network and the exact selection (2026-11-25, experiments/trajectory_design) was made with mse, and
  // it is the configuration minimax_defaults() completes.
  if (c.reference_statistic != "auto") s.fixed_statistic = parse_enum<design::ReferenceStatistic>(c.reference_statistic, "--reference-statistic");
  return s;
}

nlohmann::json design_provenance(const DesignCommand& c, bool lot_prior) {
  nlohmann::json provenance = {{"model", c.model}, {"sensor", c.sensor}, {"noise", c.noise}, {"envelope", c.envelope}, {"seed", c.seed},
                               {"solver", c.solver}, {"options", c.set}, {"command", c.command_line()}};
  if (!c.prior.empty()) provenance["prior"] = c.prior;
  if (lot_prior) provenance["calibration_prior"] = c.prior;  // the calibration designed for fits with the lot's population
  if (c.equipment != kDefaultEquipment) provenance["equipment"] = c.equipment;
  return provenance;
}

// cof_minimax or --reference: the trajectory the design must beat on every flight, calibrated with its own
// model, set as the context's reference and put first in the report. Returns its path when it is predicted
// with --model (a --compare of the same path is then not predicted again), else "".
std::string predict_reference(const DesignCommand& c, const DesignSetup& s, const SensorSpec& sensor, std::shared_ptr<const design::Envelope> envelope,
                              const design::DesignSpace& space, design::DesignContext& context, DesignReportInput& report,
                              nlohmann::json& provenance) {
  const std::string path = c.reference.empty() ? c.compare.front() : c.reference;
  const std::string model = c.reference_model.empty() ? c.model : c.reference_model;
  const TrajectorySpec spec = load_trajectory_file(path);
  const design::ModelFamily family = parse_enum<design::ModelFamily>(model, "--reference-model");
  const design::DesignContext ref_context(sensor, std::move(envelope), family, s.settings.model, design::Criterion::cof,
                                          design::model_domain(space));
  const design::Prediction ref = design::evaluate_trajectory(ref_context, spec);
  const bool same_model = family == s.family;
  context.set_reference(ref, s.fixed_statistic ? *s.fixed_statistic : same_model ? design::ReferenceStatistic::mse : design::ReferenceStatistic::cof);
  report.compared.emplace_back(str_cat(spec.profile.name, " (reference, ", model, ")"), ref);
  provenance["reference"] = {{"trajectory", path}, {"model", model}, {"predicted", prediction_json(ref)}};
  return same_model ? path : "";
}

// Designs the trajectory over the prior's members and writes trajectory.yaml, setpoints.csv, design.json,
// calibration.yaml, coverage.png and report.md into --out; the finished stages are checkpointed as it goes.
void design_and_write(const DesignCommand& c, const DesignSetup& s, const SensorPrior& prior, std::shared_ptr<const design::Envelope> envelope,
                      const design::DesignContext& context, DesignReportInput& report, const nlohmann::json& provenance) {
  // --resume continues a killed design to the same result.
  std::vector<std::string> inputs = split_list(c.envelope);
  inputs.insert(inputs.end(), {c.sensor, c.prior, c.equipment, c.reference});
  inputs.insert(inputs.end(), c.compare.begin(), c.compare.end());
  Checkpoint checkpoint = run_checkpoint(c.out, "design", run_fingerprint(*c.command, inputs), c.resume);
  design::DesignRequest request;
  request.checkpoint = &checkpoint;
  request.space = s.settings.space;
  request.quadrature = s.settings.quadrature;
  request.selection = s.settings.selection;
  request.prior = s.settings.prior;
  request.solver = c.solver;
  request.solver_options = s.solver_options;
  request.seed = c.seed;
  const PriorContexts members = prior_contexts(prior, context, std::move(envelope), s.settings.model);
  const design::DesignResult r = design::design_trajectory(members.members, request);
  report.result = &r;
  nlohmann::json design_file = design_json(r, provenance);
  if (members.members.size() > 1) {
    report.prior = prior_predictions(prior, members, r, c.compare);
    design_file["prior"] = prior_json(prior.name, prior.source, report.prior);
  }
  const std::filesystem::path dir = c.out;
  write_file_atomic(dir / "trajectory.yaml", programme_yaml(r.trajectory));
  write_file_atomic(dir / "setpoints.csv", setpoint_table_csv(r.trajectory.profile));
  write_file_atomic(dir / "design.json", design_file.dump(2) + "\n");
  write_file_atomic(dir / "calibration.yaml", design::calibration_yaml(s.family, s.settings.model, context.model_domain(), context.noise()));
  plot_design_coverage(dir / "coverage.png", design::observe_trajectory(context, r.trajectory), context.envelope(),
                       str_cat("design for ", c.envelope, " (", format_significant(r.trajectory.profile.duration_min(), 4), " min, ",
                               c.model, " model)"));
  write_file_atomic(dir / "report.md", design_report_markdown(report));
  checkpoint.finish();
  std::cout << "wrote " << c.out << "/trajectory.yaml (" << format_significant(r.trajectory.profile.duration_min(), 4) << " min, "
            << r.trajectory.profile.segments.size() << " segments), setpoints.csv, design.json, coverage.png, report.md, calibration.yaml\n"
            << "predicted: " << describe(r.predicted) << "\n";
  for (const auto& [name, p] : report.compared) std::cout << name << " (" << format_significant(p.duration_min, 4) << " min): " << describe(p) << "\n";
  std::cout << c.solver << ": " << to_string(r.summary.termination) << ", " << r.summary.evaluations << " evaluations, "
            << format_significant(r.summary.time_s, 3) << " s\n";
}

void run_design(DesignCommand c) {
  if (!c.options_of.empty()) return print_options_of(c.options_of);
  DesignSetup s = design_setup(c);
  const bool evaluating = !c.evaluate.empty();
  const SensorPrior prior = prior_with_measured_noise(c);
  if (prior.members.size() > 1 && (s.criterion == design::Criterion::cof_minimax || (evaluating && !s.lot))) {
    fail("--prior ", c.prior, ": ", evaluating ? "--evaluate takes one sensor (--sensor), or a lot" : "criterion cof_minimax takes one sensor (it compares against one reference; use --criterion cof)",
         ", not a prior of ", prior.members.size());
  }
  if (evaluating && s.lot) {
    std::cout << "evaluated for the lot's mean unit (" << prior.members.front().name << ")"
              << (s.lot_prior ? ", calibrated with the lot's prior\n" : ", calibrated by its own data alone\n");
  }
  const SensorSpec& sensor = prior.members.front().sensor;
  auto envelope = std::make_shared<const design::Envelope>(design::load_envelope(s.settings.envelope, as_triad(sensor)));
  s.settings.space.budget_min = evaluating ? 60.0 : c.budget_min;
  const design::DesignSpace space = design::design_space(*envelope, s.settings.space);
  design::DesignContext context(sensor, envelope, s.family, s.settings.model, s.criterion, design::model_domain(space));
  DesignReportInput report;
  report.command = c.command_line();
  report.model = c.model, report.sensor = c.prior.empty() ? c.sensor : c.prior, report.solver = c.solver;
  nlohmann::json provenance = design_provenance(c, s.lot_prior);
  const bool has_reference = s.criterion == design::Criterion::cof_minimax || !c.reference.empty();
  const std::string reference_as_compared = has_reference ? predict_reference(c, s, sensor, envelope, space, context, report, provenance) : "";
  for (const auto& path : evaluating ? c.evaluate : c.compare) {
    if (!evaluating && path == reference_as_compared) {  // predicted once, as the reference; the objective is the design's
      report.compared.front().second.objective = design::trajectory_objective(context, load_trajectory_file(path));
      continue;
    }
    const TrajectorySpec spec = load_trajectory_file(path);
    report.compared.emplace_back(spec.profile.name, design::evaluate_trajectory(context, spec));
  }
  if (evaluating) return write_evaluation(c, context, report, provenance);
  design_and_write(c, s, prior, envelope, context, report, provenance);
}

}  // namespace

void register_design(CLI::App& app, Action& action) {
  auto c = std::make_shared<DesignCommand>();
  CLI::App* cmd = app.add_subcommand("design", "Design a calibration trajectory by optimisation, or predict the accuracy of one");
  cmd->add_option("--budget-min", c->budget_min, "Calibration time budget, minutes");
  cmd->add_option("--model", c->model, "Calibration model the design is for: rbf, greybox, classical or hybrid (gyrosid's best noisy calibration)")->capture_default_str();
  cmd->add_option("--envelope", c->envelope, "Where the gyro will fly: flights (short, medium, long, flight .yaml/.csv), comma-separated, or uniform")
      ->capture_default_str();
  cmd->add_option("--uniform-domain", c->uniform_domain, "The uniform envelope: T_MIN_C,T_MAX_C,RATE_DPS")->capture_default_str();
  cmd->add_option("--criterion", c->criterion, "cof or cof_minimax (flights), surface, d_optimal, a_optimal or effects (greybox); default cof, surface for uniform");
  auto* sensor = cmd->add_option("--sensor", c->sensor, "Sensor config: its noise, thermal lag and error model")->capture_default_str();
  cmd->add_option("--prior", c->prior, "A prior over sensors (format gyrosid-prior/1: sensor configs with weights, and draws around "
                                       "them; docs/prior_format.md) in place of --sensor: the design minimises the weighted mean "
                                       "of its objective over the members and reports its prediction on each (criterion cof, "
                                       "surface, d_optimal, a_optimal or effects). A sensor config is a prior of one sensor")
      ->excludes(sensor);
  cmd->add_flag("--without-lot-prior", c->without_lot_prior,
                "With a lot (gyrosid lot learn) as --prior: design for its members calibrated each by its own data. By default "
                "the greybox design counts the lot's population as the calibration's prior (calibrate --prior); either "
                "way it takes the lot's grey-box structure, and --evaluate predicts for the lot's mean unit");
  cmd->add_option("--equipment", c->equipment, "Equipment file: the chamber's range and heating and cooling limits, the table's rate and "
                                               "acceleration limits (configs/equipment/thesis_lab.yaml shows every key); "
                                               "--set space.* overrides it")
      ->capture_default_str();
  cmd->add_option("--noise", c->noise, "An allan.json (gyrosid allan on a recording of the gyro): its identified noise model replaces the "
                                       "sensor config's - the design for the noise the gyro showed");
  cmd->add_option("--solver", c->solver, "Design solver: nlopt or ipopt")->capture_default_str();
  cmd->add_option("--set", c->set, "Option key=value (repeatable): solver options, or space.*, model.*, envelope.*, quadrature.*, select.* "
                  "(cof_minimax's exact final selection: select.rounds, select.emphasis, select.blend_shares); "
                  "--options-of design lists them");
  cmd->add_option("--options-of", c->options_of, "Print the options of a solver (nlopt, ipopt) or of the design (design) and exit");
  cmd->add_option("--seed", c->seed, "Seed of the solver's random streams (same seed, same design)")->capture_default_str();
  cmd->add_option("--reference", c->reference, "cof_minimax: the trajectory to beat on every flight (default: the first --compare)");
  cmd->add_option("--reference-model", c->reference_model, "The reference's calibration model (default: --model)");
  cmd->add_option("--reference-statistic", c->reference_statistic,
                  "cof_minimax: what design and reference are compared by per flight - posterior (sqrt tr S P S' of both), cof "
                  "(the reference's predicted criterion of fit against the design's posterior statistic), mse (the predicted mean "
                  "squared criterion of fit |m|^2 + tr S Sigma S' of both), mse_noise (the design's mse against the reference's noise "
                  "part tr S Sigma S' alone: a conservative gain) or auto (mse when the reference's model is --model, else cof). "
                  "cof_minimax's defaults otherwise: space.segments=10, select.rounds=1, model.network_prior=evidence")
      ->capture_default_str();
  cmd->add_option("--compare", c->compare, "Trajectories predicted beside the design in report.md")->capture_default_str();
  cmd->add_option("--evaluate", c->evaluate, "Predict the accuracy of these trajectory configs instead of designing");
  cmd->add_option("--out", c->out, "Output directory: trajectory.yaml, setpoints.csv (the programme as a controller's time-stamped "
                                   "set points), design.json, coverage.png, report.md, calibration.yaml");
  cmd->add_flag("--resume", c->resume, "Continue a killed design from its checkpoint in --out (the finished global search or "
                                       "Ipopt starts; same inputs and seed: the result equals an uninterrupted run's)");
  cmd->footer(
      "The design is a programme of table-plus-chamber segments (chamber ramps and plateaus within the chamber's\n"
      "range and rate limit, triangle rate cycles or dwells on the table) that fits the budget. Its objective is\n"
      "the calibration error the sensor's noise leaves where the gyro will fly: the model's parameter covariance\n"
      "from the Fisher information of the trajectory, pushed through the strapdown INS to the criterion of fit.\n"
      "Examples:\n"
      "  gyrosid design --budget-min 60 --out d60/\n"
      "  gyrosid design --budget-min 30 --model greybox --criterion effects --solver ipopt --out gb/\n"
      "  gyrosid design --evaluate builtin:trajectories/dual_scan.yaml builtin:trajectories/classical_soak.yaml --model classical\n"
      "  gyrosid simulate --trajectory d60/trajectory.yaml --out rec.csv");
  c->command = cmd;
  cmd->callback([c, &action] {
    action = [c] { run_design(*c); };
  });
}

}  // namespace gyrosid::cli
