// gyrosid design: optimise a calibration trajectory for a time budget, or state the predicted accuracy of
// existing trajectories (--evaluate).
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "cli/resume.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "design/design.h"
#include "design/design_solver.h"
#include "pipeline/design_job.h"
#include "report/design_report.h"
#include "trajectory/programme.h"

namespace gyrosid::cli {
namespace {

// The command line's options: the job's inputs (pipeline/design_job.h) and what only the command has.
struct DesignCommand : DesignJobInput {
  std::string out, options_of;
  bool resume = false;
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
  // A --reference (cof_minimax) comes first in report.compared, before the evaluated trajectories.
  for (const auto& [name, p] : report.compared) std::cout << name << " (" << format_significant(p.duration_min, 4) << " min): predicted " << describe(p) << "\n";
  if (!c.out.empty()) {
    write_file_atomic(dir / "evaluation.json", evaluation_json(report, c.evaluate, provenance).dump(2) + "\n");
    write_file_atomic(dir / "report.md", design_report_markdown(report));
    const TrajectorySpec first = load_trajectory_file(c.evaluate.front());
    plot_design_coverage(dir / "coverage.png", design::observe_trajectory(context, first), context.envelope(),
                         first.profile.name + ": samples over the envelope");
    std::cout << "wrote " << c.out << "/evaluation.json, report.md, coverage.png\n";
  }
}

// Designs the trajectory over the prior's members and writes trajectory.yaml, setpoints.csv, design.json,
// calibration.yaml, coverage.png and report.md into --out; the finished stages are checkpointed as it goes.
void design_and_write(const DesignCommand& c, PreparedDesign& p) {
  // --resume continues a killed design to the same result.
  std::vector<std::string> inputs = split_list(c.envelope);
  inputs.insert(inputs.end(), {c.sensor, c.prior, c.equipment, c.reference});
  inputs.insert(inputs.end(), c.compare.begin(), c.compare.end());
  Checkpoint checkpoint = checkpoint_in(c.out, "design", run_fingerprint(*c.command, inputs), c.resume);
  const DesignJobResult job = run_design_job(p, c, &checkpoint);
  const design::DesignResult& r = job.result;
  const design::DesignContext& context = *p.context;
  p.report.result = &r;
  p.report.prior = job.members;
  const std::filesystem::path dir = c.out;
  write_designed_programme(dir, r.trajectory, job.design_file);
  write_file_atomic(dir / "calibration.yaml", design::calibration_yaml(p.setup.family, p.setup.settings.model, context.model_domain(), context.noise()));
  plot_design_coverage(dir / "coverage.png", design::observe_trajectory(context, r.trajectory), context.envelope(),
                       str_cat("design for ", c.envelope, " (", format_significant(r.trajectory.profile.duration_min(), 4), " min, ",
                               p.setup.model, " model)"));
  write_file_atomic(dir / "report.md", design_report_markdown(p.report));
  checkpoint.finish();
  std::cout << "wrote " << c.out << "/trajectory.yaml (" << format_significant(r.trajectory.profile.duration_min(), 4) << " min, "
            << r.trajectory.profile.segments.size() << " segments), setpoints.csv, design.json, coverage.png, report.md, calibration.yaml\n"
            << "predicted: " << describe(r.predicted) << "\n";
  for (const auto& [name, pr] : p.report.compared) std::cout << name << " (" << format_significant(pr.duration_min, 4) << " min): " << describe(pr) << "\n";
  std::cout << c.solver << ": " << to_string(r.summary.termination) << ", " << r.summary.evaluations << " evaluations, "
            << format_significant(r.summary.time_s, 3) << " s\n";
}

void run_design(DesignCommand c) {
  if (!c.options_of.empty()) return print_options_of(c.options_of);
  if (c.evaluate.empty() && c.budget_min > 0 && c.out.empty()) fail("--out DIR is required for a design");
  c.invocation = c.command_line();
  PreparedDesign p = prepare_design(c, std::cout);
  if (!c.evaluate.empty()) return write_evaluation(c, *p.context, p.report, p.provenance);
  design_and_write(c, p);
}

}  // namespace

void register_design(CLI::App& app, Action& action) {
  auto c = std::make_shared<DesignCommand>();
  CLI::App* cmd = app.add_subcommand("design", "Design a calibration trajectory by optimisation, or predict the accuracy of one");
  cmd->add_option("--budget-min", c->budget_min, "Calibration time budget, minutes");
  cmd->add_option("--model", c->model, "Calibration model the design is for: rbf, greybox, classical, hybrid (gyrosid's best noisy calibration), "
                                       "or auto - the one gyrosid calibrate fits on the recording: greybox under a lot (--prior lot.json), "
                                       "else the hybrid, its preset for a noisy gyro")->capture_default_str();
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
  cmd->add_option("--solver", c->solver, "Design solver: " + join(design::design_solvers().names(), ", ", " or "))->capture_default_str();
  cmd->add_option("--set", c->set, "Option key=value (repeatable): solver options, or space.*, model.*, envelope.*, quadrature.*, select.* "
                  "(cof_minimax's exact final selection: select.rounds, select.emphasis, select.blend_shares); "
                  "--options-of design lists them");
  cmd->add_option("--options-of", c->options_of, str_cat("Print the options of a solver (", design::design_solvers().known(), ") or of the design (design) and exit"));
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
