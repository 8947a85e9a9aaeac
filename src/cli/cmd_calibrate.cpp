// gyrosid calibrate: fit a calibration model to a recording (solvers/calibrate.h).
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include "cli/app.h"
#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "model/calibration_model.h"
#include "model/fit_notes.h"
#include "pipeline/calibrate_job.h"
#include "pipeline/lot_jobs.h"
#include "solvers/calibrate.h"
#include "solvers/nls/nls_solver.h"
#include "solvers/solver.h"
#include "solvers/triad/triad_fit.h"

namespace gyrosid::cli {
namespace {

struct CalibrateOptions {
  std::string config, recording, model, solver, out, features, target, normalization, help_for, surfaces, axis, decimate, prior;
  bool joint = false, sequential = false, auto_estimation = false;
  std::vector<std::string> set;
};

// The calibration asked for: a YAML config's defaults (its recording and out too, unless given), the
// command line's values over them, or a lot's prior (its grey-box structure, the MAP under its population).
CalibrationRequest request_of(CalibrateOptions& o) {
  CalibrationRequest request;
  if (!o.config.empty()) {
    const ConfigNode c = ConfigNode::load(o.config);
    request = calibration_request_from_config(c, {"recording", "out"});
    if (o.recording.empty() && c.has("recording")) o.recording = c.resolve(c.text("recording"));
    if (o.out.empty() && c.has("out")) o.out = c.resolve(c.text("out"));
  }
  if (o.recording.empty()) fail("--recording is required (or 'recording' in --config)");
  if (o.out.empty()) fail("--out is required (or 'out' in --config)");
  if (!o.model.empty()) request.model = o.model;
  if (!o.solver.empty()) request.solver = o.solver;
  if (!o.features.empty()) request.features = split_list(o.features);
  if (!o.target.empty()) request.target = parse_enum<ModelTarget>(o.target, "--target");
  if (!o.normalization.empty()) request.normalization = parse_enum<NormalizationKind>(o.normalization, "--normalization");
  for (auto& [key, value] : parse_options(o.set)) request.options[key] = std::move(value);
  // The triad's --set surfaces=... and estimation=... by their older spellings.
  if (int(o.joint) + int(o.sequential) + int(o.auto_estimation) > 1) fail("--joint, --sequential and --auto exclude each other");
  if (!o.surfaces.empty()) request.options["surfaces"] = o.surfaces;
  if (o.joint || o.sequential || o.auto_estimation) request.options["estimation"] = o.joint ? "joint" : o.sequential ? "sequential" : "auto";
  if (!o.prior.empty()) {
    if (!o.model.empty() && o.model != "greybox") fail("--prior (a lot file) calibrates the greybox model, not --model ", o.model);
    if (!o.set.empty() || !o.config.empty()) fail("--prior fixes the model's structure to the lot's: --set and --config do not apply");
    take_lot_prior(request, load_lot(o.prior));
  }
  return request;
}

// "a, b (note), c": a registry's names for help text, each name in `notes` annotated.
std::string noted(std::vector<std::string> names, const std::map<std::string, std::string>& notes) {
  for (std::string& name : names) {
    if (const auto it = notes.find(name); it != notes.end()) name += str_cat(" (", it->second, ")");
  }
  return join(names);
}

// What the fit says beside its model: left-out physics, a lot prior's share and predictive sigma, the noise.
void print_fit_notes(const FitNotes& n) {
  if (n.physics_left_out) std::cout << "physics: " << n.physics_left_out->note << "\n";
  if (!n.data_share.empty()) {
    std::cout << "share of each term's information from the recording (1) or the lot's prior (0):";
    for (const auto& [group, share] : n.data_share) std::cout << " " << group << " " << format_significant(share, 2);
    std::cout << "\n";
  }
  if (const auto& ps = n.predictive_sigma) {  // where the prior filled in: the estimate's sd is largest there
    std::cout << "predictive sigma of the estimated error over the surface grid's nodes: rms " << format_significant(ps->rms_dph, 3)
              << " deg/h, max " << format_significant(ps->max_dph, 3) << " deg/h at " << format_number(ps->max_at_temp_c)
              << " C, " << format_number(ps->max_at_rate_dps) << " deg/s\n";
  }
  if (!n.physics_note.empty()) std::cout << "physics: " << n.physics_note << "\n";
  if (!n.noise_choice.empty()) std::cout << "noise model: " << n.noise_choice << "\n";
  if (!n.noise_identification.empty()) std::cout << "noise identification of the residual (as gyrosid allan would give it): " << n.noise_identification << "\n";
}

void run_calibrate(CalibrateOptions o) {
  if (!o.help_for.empty()) {
    std::cout << (model_fitters().find(o.help_for) ? model_help(o.help_for) : solver_help(o.help_for));
    return;
  }
  CalibrationRequest request = request_of(o);
  // Nothing chosen: the job characterises the noise and picks the preset for it, saying why.
  const bool choose = o.config.empty() && o.model.empty() && o.solver.empty() && request.options.empty() && o.features.empty() &&
                      o.target.empty() && o.normalization.empty() && o.prior.empty();
  CalibrateJobInput input;
  if (!choose) input.request = request;
  input.decimate = o.decimate;
  input.on_step = [](const std::string& what) { progress_note(what); };
  const CalibrateJobResult job = run_calibrate_job(o.recording, o.axis, input);
  const ModelFit& fit = job.fit;
  if (job.decimation.applied()) std::cout << job.decimation.statement() << "\n";
  if (job.choice) {
    for (const auto& line : job.choice->reasons) std::cout << line << "\n";
  }
  if (!job.averaging_statement.empty()) std::cout << job.averaging_statement << "\n";
  const FitNotes& notes = job.notes;
  print_fit_notes(notes);
  save_model(o.out, *fit.model, fit.extra);
  std::cout << "wrote " << o.out << ": " << fit.model->kind() << " model";
  const SolveSummary& s = fit.summary;
  if (notes.nodes) std::cout << ", " << notes.size();
  std::cout << ", " << to_string(s.termination);
  if (!s.message.empty()) std::cout << " (" << s.message << ")";
  std::cout << ", " << format_significant(s.time_s, 3) << " s, peak " << format_significant(s.peak_rss_mb, 3) << " MB";
  std::cout << "\n";
  for (const std::string& line : fit.statement) std::cout << line << "\n";
  for (const std::string& w : fit.warnings) std::cerr << "warning: " << w << "\n";
}

}  // namespace

void register_calibrate(CLI::App& app, Action& action) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand("calibrate", str_cat("Fit a calibration model (", model_fitters().known(), ") to a recording; without options, a preset chosen from its noise"));
  cmd->add_option("--recording", o->recording, "Training recording: a single gyro with ref_rate_dps, a triad recording with --axis, or for --model triad the triad's");
  cmd->add_option("--model", o->model, str_cat(noted(model_fitters().names(), {{"hybrid", "physics + Bayesian RBF"},
                                                                                     {"triad", "three gyros: misalignment, biases, surfaces"}}),
                                               "; a kind's options: --options-of <model>"));
  cmd->add_option("--solver", o->solver, str_cat("RBF solver: ", noted(rbf_solvers().names(), {{CalibrationRequest{}.solver, "default with --model rbf"}}),
                                                  "; triad: ", noted(nls_solvers().names(), {{TriadFitOptions{}.solver, "default"}})));
  // The triad's options are --set surfaces=... and estimation=...; these four spellings of them are kept for
  // scripts that use them, out of the help (a kind's own options are listed by --options-of).
  cmd->add_option("--surfaces", o->surfaces, "triad: --set surfaces=...")->group("");
  cmd->add_flag("--joint", o->joint, "triad: --set estimation=joint")->group("");
  cmd->add_flag("--sequential", o->sequential, "triad: --set estimation=sequential")->group("");
  cmd->add_flag("--auto", o->auto_estimation, "triad: --set estimation=auto")->group("");
  cmd->add_option("--set", o->set, "Solver or model option key=value (repeatable); see --options-of");
  cmd->add_option("--features", o->features, "Model inputs, comma-separated (default measured_rate,temperature)");
  cmd->add_option("--target", o->target, "error (default: model the rate error) or corrected_rate");
  cmd->add_option("--normalization", o->normalization, "Input normalisation: range (default) or units (deg/s, deg C)");
  cmd->add_option("--axis", o->axis, "Triad recordings: the gyro a single-gyro model is fitted to (x, y or z)");
  cmd->add_option("--decimate", o->decimate,
                  str_cat("Block means of b samples before fitting: auto (the smallest b that leaves at most ", DecimationRequest{}.target_rows,
                          " samples; the default without --model, --solver, --set or --config), none (the default otherwise), or b; "
                          "never across a gap; the factor, the new interval, each input's within-block spread and the fitted "
                          "model's averaging bias are stated"));
  cmd->add_option("--prior", o->prior,
                  "A lot file (gyrosid lot learn): the greybox model with the lot's structure, fitted as the maximum a posteriori under "
                  "the lot's population - the recording decides what it determines, the lot the rest; the share of each is printed, and the "
                  "predictive sigma over the surface grid (the model keeps its posterior: largest where the lot filled in)");
  cmd->add_option("--config", o->config, "YAML with any of: recording, model, solver, features, target, normalization, options, out");
  cmd->add_option("--options-of", o->help_for, "Print the options of a solver or model and exit");
  cmd->add_option("--out", o->out, "Model file to write (JSON)");
  cmd->footer(
      "Examples:\n"
      "  gyrosid calibrate --recording train.csv --model rbf --solver ols --set criterion=bic --set width=0.2 --out m.json\n"
      "  gyrosid calibrate --recording soak.csv --model classical --out classical.json\n"
      "  gyrosid calibrate --options-of ceres\n"
      "  gyrosid calibrate --model triad --recording triad.csv --set surfaces=classical --set estimation=joint --solver ceres --out triad.json\n"
      "  gyrosid calibrate --options-of triad      (triad options, nls back-ends)\n"
      "  gyrosid calibrate --recording unit_15min.csv --prior lot.json --out unit.json   (a new unit of a lot)\n"
      "Without --model, --solver, --set or --config the recording's noise is characterised and a preset chosen\n"
      "(builtin:calibration/rbf_noise_free.yaml or rbf_noisy.yaml); what was measured and why is printed.\n"
      "The thesis's configuration: --solver ols --normalization units --set width=17.5 --set criterion=bic\n"
      "(Orr's toolbox on deg/s and deg C with node scale 17.5).");
  cmd->callback([o, &action] { action = [o] { run_calibrate(*o); }; });
}

}  // namespace gyrosid::cli
