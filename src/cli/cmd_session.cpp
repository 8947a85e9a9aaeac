// gyrosid session: an adaptive calibration session - a pilot, an update of the prior over sensors by the
// recording, a redesign of the remaining time, and the final calibration (pipeline/session.h).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "pipeline/session.h"

namespace gyrosid::cli {

namespace {

struct SessionCommand {
  SessionOptions session;
  std::string out;
  std::vector<std::string> set;
};

void run(SessionCommand& c) {
  SessionOptions& o = c.session;
  o.out = c.out;
  o.set(parse_options(c.set));
  o.on_step = [](const std::string& what) { progress_note(what); };
  const SessionResult r = run_session(o);
  if (r.session["prior"].contains("lot")) std::cout << r.session["prior"]["lot"].get<std::string>() << "\n";
  if (r.waiting_for) {
    std::cout << "designed segment " << r.segments_done + 1 << " of " << r.segments << ": run " << c.out << "/segment_" << r.segments_done + 1
              << "/trajectory.yaml (setpoints.csv), record it to " << r.waiting_for->string()
              << " (gyrosid-recording/1, times from the segment's start), then run the same command with --resume\n";
    return;
  }
  for (const auto& seg : r.session["segments"]) {
    const auto& post = seg["posterior"];
    std::size_t top = 0;
    for (std::size_t m = 0; m < post["members"].size(); ++m) {
      if (post["members"][m]["weight"] > post["members"][top]["weight"]) top = m;
    }
    std::cout << "segment " << seg["segment"] << " (" << format_significant(seg["start_min"], 4) << "-"
              << format_significant(seg["start_min"].get<double>() + seg["duration_min"].get<double>(), 4) << " min): designed for "
              << seg["designed_for"].size() << " members; then " << format_significant(post["effective_members"], 3)
              << " effective (likelihood power " << format_significant(post["learning_rate"], 3) << "), most likely "
              << post["members"][top]["name"].get<std::string>() << " (" << format_significant(post["members"][top]["weight"], 3) << ")\n";
  }
  std::cout << "predicted criterion of fit (weighted mean [least, largest] over the posterior's members):";
  for (const auto& [flight, band] : r.session["final"]["predicted"].items()) {
    std::cout << " " << flight << " " << format_significant(band["cof_mean_m"], 3) << " m [" << format_significant(band["cof_min_m"], 3) << ", "
              << format_significant(band["cof_max_m"], 3) << "]";
  }
  std::cout << "\nwrote " << c.out << "/session.json (" << r.segments << " segments), recording.csv, trajectory.yaml, model.json\n";
}

}  // namespace

void register_session(CLI::App& app, Action& action) {
  auto c = std::make_shared<SessionCommand>();
  SessionOptions& o = c->session;
  CLI::App* cmd = app.add_subcommand("session", "An adaptive calibration session: a pilot, the prior updated by the recording, a redesign of the rest");
  cmd->add_option("--prior", o.prior,
                  "The prior over sensors (gyrosid-prior/1, docs/prior_format.md), or one sensor config; a lot (gyrosid lot learn) with "
                  "--model greybox (auto's choice for a lot with a grey-box structure) also gives its structure, and its population as "
                  "every calibration's prior (calibrate --prior)")
      ->required();
  cmd->add_option("--truth", o.truth, "Simulation: the true sensor config, which the session sees only through its recordings. "
                                      "Without it the session stops after each designed segment for the lab's recording");
  cmd->add_option("--budget-min", o.budget_min, "Total time, minutes")->capture_default_str();
  cmd->add_option("--pilot-min", o.pilot_min, "The pilot: the first segment, designed for the prior, minutes")->capture_default_str();
  cmd->add_option("--update-at-min", o.updates_at_min, "Further updates and redesigns, minutes from the start (repeatable)");
  cmd->add_option("--model", o.model, "Calibration model the designs are for: rbf, greybox, classical, hybrid, or auto - as gyrosid design's: "
                                    "greybox under a lot (with its structure), else the hybrid")->capture_default_str();
  cmd->add_option("--calibration", o.calibration, "Calibration config of the interim and final fits (default: the design's, written as calibration.yaml)");
  cmd->add_option("--envelope", o.envelope, "Flights the gyro will fly (short, medium, long, flight files), comma-separated")->capture_default_str();
  cmd->add_option("--equipment", o.equipment, "Equipment file: the chamber's and table's limits")->capture_default_str();
  cmd->add_option("--set", c->set, "key=value (repeatable): design options (gyrosid design --options-of design), nlopt options, "
                                   "session.min_effective_members (the posterior's tempering floor, default 2) or session.drop_share "
                                   "(members below this posterior weight are left out of a redesign, default 0.001)");
  cmd->add_option("--seed", o.seed, "Seed of the designs and of the simulated truth")->capture_default_str();
  cmd->add_option("--out", c->out, "Output directory: session.json, calibration.yaml, segment_k/ (trajectory.yaml, setpoints.csv, "
                                   "design.json, recording.csv, model.json), and at the end recording.csv, trajectory.yaml, model.json")
      ->required();
  cmd->add_flag("--resume", o.resume, "Continue the session in --out: after a kill, or after the lab recorded the segment it waits for");
  cmd->footer(
      "Segment 1 (the pilot) is the design for the prior. After each segment every member of the prior is scored\n"
      "by its likelihood of all that is recorded (its noise-free output on the programme, its own noise, a free\n"
      "bias), the weights become the tempered posterior (at least session.min_effective_members effective members),\n"
      "and the next segment is designed for that posterior as the continuation of what is recorded: the design\n"
      "counts the information already gathered. The last step calibrates on everything recorded.\n"
      "session.json holds each segment's members and weights, the predicted criterion of fit per flight before and\n"
      "after each update (weighted mean, least and largest over the members), and the log-likelihoods.\n"
      "Examples:\n"
      "  gyrosid session --prior builtin:priors/open_loop_fog_type.yaml --truth my_gyro.yaml --budget-min 60 --seed 1 --out s/\n"
      "  gyrosid session --prior builtin:priors/open_loop_fog_type.yaml --budget-min 60 --out lab/     # designs segment 1, stops\n"
      "  gyrosid session --prior builtin:priors/open_loop_fog_type.yaml --budget-min 60 --out lab/ --resume   # after recording it\n"
      "  gyrosid cof --model s/model.json --flight long");
  cmd->callback([c, &action] {
    action = [c] { run(*c); };
  });
}

}  // namespace gyrosid::cli
