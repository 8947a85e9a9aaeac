// gyrosid explain: find which physics a simulation left out of a recording, model it, prove the fit better.
#include <iostream>
#include <memory>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "cli/app.h"
#include "cli/resume.h"
#include "core/error.h"
#include "core/format.h"
#include "core/decimation.h"
#include "core/recording.h"
#include "core/recording_reader.h"
#include "explain/explain.h"
#include "report/explain_json.h"
#include "report/explain_report.h"

namespace gyrosid::cli {
namespace {

struct ExplainCommand {
  std::string recording, out, baseline_form = "auto", noise_model = "full", decimate = "auto";
  explain::ExplainOptions options;
  bool resume = false;
  const CLI::App* command = nullptr;  // the parsed subcommand, for the checkpoint's fingerprint
};

void run_explain(ExplainCommand c) {
  c.options.baseline_form = parse_enum<explain::BaselineForm>(c.baseline_form, "--baseline-form");
  c.options.selection.noise_model = parse_enum<explain::NoiseModelSource>(c.noise_model, "--noise-model");
  const DecimationRequest decimation = DecimationRequest::parse(c.decimate, "--decimate");
  const std::vector<std::string> spread = explain::explain_spread_columns(RecordingReader(c.recording).names(), c.options.input.axis);
  const DecimatedRecording rec = read_decimated(c.recording, decimation, spread);
  if (rec.decimation.applied()) std::cout << rec.decimation.statement() << "\n";
#ifdef __GLIBC__
  // explain fits N x p whitened designs of a few MB thousands of times; by default glibc returns each freed
  // block to the kernel (mmap threshold, heap trimming) and faults it in again at the next allocation - a
  // sixth of an 8-h recording's CPU time went to the kernel. Freed memory is kept in the process instead.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest on 64-bit
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
  // Every finished selection step's bootstrap is saved; --resume continues a killed run to the same result.
  Checkpoint checkpoint = checkpoint_in(c.out, "explain", run_fingerprint(*c.command, {c.recording, c.options.model_path, c.options.baseline_path}),
                                         c.resume);
  const explain::ExplainResult r = explain::explain_recording(rec.recording, c.options, &checkpoint, &rec.decimation);
  write_explain_outputs(r, c.out);
  checkpoint.finish();
  const explain::ExplainSummary& j = r.summary;
  if (!j.recording.decimation.is_null()) std::cout << j.recording.decimation["statement"].get<std::string>() << "\n";
  std::cout << "verdict: " << to_string(j.verdict);
  for (const auto& e : j.effects) {
    std::cout << "\n  effect " << e.id << " (dBIC " << format_significant(e.delta_bic, 3) << ", p " << format_significant(e.p_value, 2) << ")";
    if (!e.alternatives.empty()) std::cout << ", cannot be told apart from " << nlohmann::json(e.alternatives).dump();
  }
  for (const auto& u : j.unexplained) std::cout << "\n  unexplained " << to_string(u.kind) << (u.channel ? " " + *u.channel : "");
  const auto& f = j.fit;
  std::cout << "\nresidual rms " << format_significant(f.rms_before_dph, 4) << " -> " << format_significant(f.rms_after_dph, 4)
            << " deg/h (held out " << format_significant(f.heldout_rms_before_dph, 4) << " -> " << format_significant(f.heldout_rms_after_dph, 4)
            << "), noise floor " << format_significant(j.noise.floor_dph, 4) << " deg/h\nrun time " << format_significant(j.run_time_s, 3) << " s:";
  for (const auto& [stage, s] : j.stage_times.seconds) std::cout << " " << stage << " " << format_significant(s, 2) << ";";
  std::cout << "\nwrote " << c.out
            << "/explain.json, residuals.csv, model.json, report.md\n";
}

// The effect library for --help, from the registry.
std::string effects_help() {
  std::string out;
  for (const auto& e : explain::effect_registry().entries()) out += "  " + e.name + ": " + e.help() + "\n";
  return out;
}

}  // namespace

void register_explain(CLI::App& app, Action& action) {
  auto c = std::make_shared<ExplainCommand>();
  CLI::App* cmd = app.add_subcommand("explain", "Find the physics a simulation left out of a recording, model it, show the fit improve");
  cmd->add_option("--recording", c->recording, "The recording to explain (gyrosid-recording/1)")->required();
  auto* model = cmd->add_option("--model", c->options.model_path, "The simulation as a saved model (any model calibrate writes)");
  cmd->add_option("--baseline", c->options.baseline_path, "Or: a calibration recording to fit the baseline family on")->excludes(model);
  cmd->add_option("--baseline-form", c->baseline_form, "Scale factor of the baseline family (without --model, or for a black-box model): surface (a bicubic surface on the thesis grid, "
                  "about 100 columns), polynomial (omega dT^i u^j, i, j <= 3: 16 columns), or auto (the surface only where its BIC on the "
                  "training rows is below the polynomial's: flexibility the data do not need would absorb physics such as a scale-factor asymmetry)")
      ->capture_default_str();
  cmd->add_option("--noise-model", c->noise_model,
                  "Whitening model once from the full model's residual (full) or from the current model at every step (current: conservative)")
      ->capture_default_str();
  cmd->add_option("--axis", c->options.input.axis, "Triad recordings: the gyro to explain (x, y or z)");
  cmd->add_option("--decimate", c->decimate,
                  str_cat("Block means of b samples before explaining: auto (the smallest b that leaves at most ", DecimationRequest{}.target_rows,
                          " samples), none, or b; never across a gap; the factor, the new interval and each input's within-block spread are stated"))
      ->capture_default_str();
  cmd->add_option("--effects", c->options.effects, "Restrict the library to these effects (comma-separated ids)");
  cmd->add_option("--alpha", c->options.selection.alpha, "Family-wise error rate over the library (Holm)")->capture_default_str();
  cmd->add_option("--bootstrap", c->options.selection.bootstrap, "Block-bootstrap resamples for the p-values (raised to 2m/alpha for m candidates when fewer: below it no p-value could pass Holm)")->capture_default_str();
  cmd->add_option("--max-effects", c->options.selection.max_effects, "Forward-selection steps at most")->capture_default_str();
  cmd->add_option("--likelihood-tries", c->options.selection.likelihood_tries,
                  "Candidates per forward step the likelihood gate maximises the noise for, from each of two rankings: their dBIC at the null's noise, and at the step's whitening (where a change the null's noise absorbed still scores)")
      ->capture_default_str();
  cmd->add_option("--seed", c->options.selection.seed, "Seed of the bootstrap")->capture_default_str();
  cmd->add_option("--heldout-every", c->options.input.heldout_every,
                  "Hold out every n-th block (from the third when n > 2): it only confirms, never fits")
      ->capture_default_str();
  cmd->add_option("--out", c->out, "Output directory: explain.json, residuals.csv, model.json, report.md, plots")->required();
  cmd->add_flag("--resume", c->resume, "Continue a killed run from its checkpoint in --out (the finished selection steps' "
                                       "bootstraps; same inputs and seed: the result equals an uninterrupted run's)");
  c->command = cmd;
  cmd->footer(str_cat(
      "The simulation: with --model a saved model predicts the recording; with --baseline the baseline family (bias\n"
      "cubic in T, scale factor a polynomial of order 3 in T and omega) is fitted on that calibration recording; with\n"
      "neither it is fitted on this recording's training blocks. Its coefficients are re-estimated either way.\n"
      "Effects (--effects; parameters with their units):\n",
      effects_help(),
      "Blocks: whole thermal cycles when the recording has four or more, else eight spans of time; every\n"
      "--heldout-every-th block (default ", explain::InputOptions{}.heldout_every, ") from the third is held out and only confirms.\n"
      "An effect the held-out blocks do not hold (a warm-up at the start, an onset after the last of them) is\n"
      "confirmed instead by blocked cross-validation on its own support (explain.json: support_z). A change whose time\n"
      "lies in a held-out block is confirmed by the blocks after it and reported as lying in that block.\n"
      "Example: gyrosid explain --recording lab.csv --model sim.json --out why/"));
  cmd->callback([c, &action] { action = [c] { run_explain(*c); }; });
}

}  // namespace gyrosid::cli
