// gyrosid lot: a production lot - learn the population of a gyro type from calibrated units (lot/lot_model.h)
// and screen a unit against it (lot/screen.h). `gyrosid calibrate --prior lot.json` fits a new unit with it.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "cli/app.h"
#include "cli/resume.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/recording.h"
#include "lot/lot_members.h"
#include "lot/lot_unit.h"
#include "lot/screen.h"
#include "model/calibration_model.h"
#include "model/greybox_model.h"
#include "solvers/calibrate.h"

namespace gyrosid::cli {
namespace {

struct LotLearnCommand {
  std::vector<std::string> recordings, models, screen_recordings, set;
  std::string name, out;
  double package_tau_s = LotMemberOptions{}.package_tau_s;
  bool resume = false;
  const CLI::App* command = nullptr;  // the parsed subcommand, for the checkpoint's fingerprint
};

struct LotScreenCommand {
  std::vector<std::string> recordings;
  std::string prior, out;
  double alpha = ScreenOptions{}.alpha;
  bool resume = false;
  const CLI::App* command = nullptr;
};

// The checkpoint of a lot command writing `out` (a file: beside it; a directory: in it), fingerprinted by
// its options and every file it reads.
Checkpoint lot_checkpoint(const CLI::App& command, const std::filesystem::path& out, bool out_is_dir, std::vector<std::string> files,
                          bool resume) {
  const std::filesystem::path dir = out_is_dir ? out : out.parent_path().empty() ? std::filesystem::path(".") : out.parent_path();
  std::filesystem::create_directories(dir);
  return run_checkpoint(dir.string(), out_is_dir ? "lot_screen" : out.filename().string(), run_fingerprint(command, files), resume);
}

// Already-calibrated grey-box units: the structure from the first (its bias order and surface grid, and a
// term wherever some unit has it).
std::vector<LotUnit> units_of_models(const std::vector<std::string>& paths, OptionMap& structure) {
  std::vector<std::unique_ptr<GreyboxModel>> models;
  for (const auto& path : paths) {
    std::unique_ptr<CalibrationModel> m = load_model(path);
    auto* g = dynamic_cast<GreyboxModel*>(m.get());
    if (!g) fail(path, ": a lot learns from greybox models; this is a ", m->kind(), " model");
    m.release();
    models.emplace_back(g);
  }
  const GyroErrorModel& first = models.front()->errors();
  if (!first.scale_factor_surface) fail(paths.front(), ": a lot needs the scale-factor surface form");
  structure["bias_order"] = std::to_string(std::max<int>(0, static_cast<int>(first.bias_temperature_radps.coefficients.size()) - 1));
  structure["surface_temperatures_c"] = format_numbers(first.scale_factor_surface->x(), ",");
  structure["surface_rates_dps"] = format_numbers(surface_grid_rates_dps(*first.scale_factor_surface), ",");
  for (const auto& m : models) {
    if (m->errors().shupe_rad_per_c != 0.0) structure["shupe"] = "true";
    if (m->errors().scale_factor_asymmetry != 0.0) structure["asymmetry"] = "true";
    if (m->errors().g_sensitivity.any()) structure["g_sensitivity"] = "true";
    if (m->lag_tau_s() > 0.0) structure["thermal_lag"] = "true";
  }
  const GreyboxOptions o = greybox_options(structure);
  std::vector<LotUnit> units;
  for (std::size_t i = 0; i < paths.size(); ++i) units.push_back(unit_of_model(*models[i], paths[i], o));
  return units;
}

void run_learn(const LotLearnCommand& c) {
  if (c.recordings.empty() == c.models.empty()) fail("give exactly one of --recordings (each unit calibrated here) or --models (greybox model files)");
  OptionMap greybox, lot_settings;
  for (const auto& kv : c.set) {
    const auto [key, value] = split_option(kv);
    (key.rfind("lot.", 0) == 0 ? lot_settings[key.substr(4)] : greybox[key]) = value;
  }
  if (!c.models.empty() && !greybox.empty()) fail("--set greybox options apply to --recordings; --models keep the structure they were calibrated with");
  LotOptions options;
  options.table().apply(lot_settings);
  // The units' calibrations are saved batch by batch; --resume continues a killed run to the same bytes.
  std::vector<std::string> inputs = c.recordings;
  inputs.insert(inputs.end(), c.models.begin(), c.models.end());
  inputs.insert(inputs.end(), c.screen_recordings.begin(), c.screen_recordings.end());
  Checkpoint checkpoint = lot_checkpoint(*c.command, c.out, false, inputs, c.resume);
  const GreyboxOptions structure = greybox_options(greybox);
  const std::vector<LotUnit> units = c.models.empty() ? calibrate_units(c.recordings, structure, "lot learn: calibrating the units", &checkpoint)
                                                      : units_of_models(c.models, greybox);
  progress_note(str_cat("lot learn: the population of ", units.size(), " units"));
  std::vector<LotUnit> screen_units;
  if (!c.screen_recordings.empty()) {
    screen_units = calibrate_units(c.screen_recordings, structure, "lot learn: the units' screening recordings", &checkpoint, "screen_units");
  }
  LotModel lot = learn_lot(units, greybox, options, c.screen_recordings.empty() ? nullptr : &screen_units);
  if (!c.recordings.empty() && !single_coordinate_terms(lot.coordinates).empty()) {
    // The conditional tests' null: the null's units' recordings, each refitted with the lot learned without it.
    const std::vector<std::string>& probes = c.screen_recordings.empty() ? c.recordings : c.screen_recordings;
    std::vector<std::string> paths;
    for (std::size_t u : lot.null_units) paths.push_back(probes[u]);
    set_conditional_nulls(lot, conditional_scores(paths, lot, "lot learn: the conditional tests' null", &checkpoint, "conditional",
                                                  [&](std::size_t k) { return lot_without(lot, units, lot.null_units[k], options); }));
  }
  write_file_atomic(c.out, lot_prior_file(lot, c.name, {c.package_tau_s}).dump(1) + "\n");
  checkpoint.finish();
  std::cout << "wrote " << c.out << ": " << lot.unit_names.size() << " units, " << lot.coordinates.size() << " coordinates, " << lot.modes.cols()
            << " modes (";
  double total = lot.mode_variance.sum() + lot.residual_variance * static_cast<double>(lot.coordinates.size() - lot.modes.cols());
  std::cout << format_significant(100.0 * lot.mode_variance.sum() / total, 3) << " % of the standardised variance)";
  if (lot.noise_units > 0) std::cout << ", white noise " << format_significant(std::exp(lot.log_noise_mean), 3) << " dph at 1 Hz x/ " << format_significant(std::exp(lot.log_noise_sd), 3);
  std::cout << "\n";
  if (!lot.left_out.empty()) std::cout << "left out as out of family (leave-one-out p < " << options.trim_alpha << "): " << join(lot.left_out) << "\n";
}

// A CSV field: quoted, its quotes doubled (RFC 4180).
std::string csv_field(const std::string& text) {
  std::string q = "\"";
  for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

void print_screen(const std::string& recording, const ScreenResult& r, double alpha) {
  std::cout << recording << ": " << (r.out_of_family ? "OUT OF FAMILY" : "in family") << " (p = " << format_significant(r.p_value, 3)
            << "; physics " << format_significant(r.p_physics, 3) << ", noise " << format_significant(r.p_noise, 3) << "; alpha " << alpha << ")\n";
  for (const auto& reason : r.reasons) std::cout << "  " << reason << "\n";
  if (!r.warning.empty()) std::cout << "warning: " << r.warning << "\n";
}

// Each unit's screen.json: in --out for one recording; for several, in --out/<its path from the recordings'
// common folder, without the extension>/ (units/a.csv -> a/, lot/u0007/short.csv -> u0007/short/), with
// screens.csv, a row per unit, beside them.
std::vector<std::filesystem::path> screen_dirs(const LotScreenCommand& c) {
  const std::filesystem::path out(c.out);
  if (c.recordings.size() == 1) return {out};
  std::vector<std::filesystem::path> paths;
  for (const auto& r : c.recordings) paths.push_back(std::filesystem::absolute(r).lexically_normal());
  std::filesystem::path common = paths.front().parent_path();
  for (const auto& p : paths) {
    while (!common.empty() && p.lexically_relative(common).begin()->string() == "..") common = common.parent_path();
  }
  std::vector<std::filesystem::path> dirs;
  std::map<std::filesystem::path, std::string> seen;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    std::filesystem::path name = paths[k].lexically_relative(common);
    name.replace_extension();
    if (auto [it, fresh] = seen.emplace(name, c.recordings[k]); !fresh) {
      fail("--recording ", it->second, " and ", c.recordings[k], " would both be screened into ", (out / name).string());
    }
    dirs.push_back(out / name);
  }
  return dirs;
}

void run_screen(const LotScreenCommand& c) {
  const LotModel lot = load_lot(c.prior);
  const std::vector<std::filesystem::path> dirs = screen_dirs(c);
  std::vector<std::string> inputs = c.recordings;
  inputs.push_back(c.prior);
  Checkpoint checkpoint = lot_checkpoint(*c.command, c.out, true, inputs, c.resume);
  const std::vector<LotUnit> units = calibrate_units(c.recordings, lot.structure, "lot screen: calibrating the units with the lot's structure", &checkpoint,
                                                     "units", lot.conditional_terms.empty() ? nullptr : &lot);
  std::string table = "recording,out_of_family,p_value,p_physics,p_noise,white_dph_at_1hz,first_reason\n";
  int flagged = 0;
  for (std::size_t k = 0; k < units.size(); ++k) {
    const ScreenResult r = screen_unit(lot, units[k], {c.alpha});
    nlohmann::json j = r.to_json();
    j["recording"] = c.recordings[k];
    j["prior"] = c.prior;
    j["alpha"] = c.alpha;
    j["white_dph_at_1hz"] = units[k].white_dph_at_1hz;
    std::filesystem::create_directories(dirs[k]);
    write_file_atomic(dirs[k] / "screen.json", j.dump(2) + "\n");
    flagged += r.out_of_family;
    if (c.recordings.size() == 1 || r.out_of_family) print_screen(c.recordings[k], r, c.alpha);
    table += str_cat(csv_field(c.recordings[k]), ",", r.out_of_family ? "true" : "false", ",", format_number(r.p_value), ",", format_number(r.p_physics), ",",
                     format_number(r.p_noise), ",", format_number(units[k].white_dph_at_1hz), ",", csv_field(r.reasons.empty() ? "" : r.reasons.front()), "\n");
  }
  if (c.recordings.size() == 1) {
    std::cout << "wrote " << (dirs.front() / "screen.json").string() << "\n";
  } else {
    write_file_atomic(std::filesystem::path(c.out) / "screens.csv", table);
    std::cout << flagged << " of " << units.size() << " units out of family at alpha " << c.alpha << "; wrote " << units.size() << " screen.json and "
              << (std::filesystem::path(c.out) / "screens.csv").string() << "\n";
  }
  checkpoint.finish();
}

}  // namespace

void register_lot(CLI::App& app, Action& action) {
  CLI::App* lot = app.add_subcommand("lot", "A production lot: learn a gyro type's population from its units, screen a unit against it");
  lot->require_subcommand(1);
  auto l = std::make_shared<LotLearnCommand>();
  CLI::App* learn = lot->add_subcommand("learn", "Learn the lot's population (physics terms' mean and low-rank covariance, noise) from N units");
  learn->add_option("--recordings", l->recordings, "Each unit's recording (single gyro, with ref_rate_dps); each is calibrated with the greybox model");
  learn->add_option("--models", l->models, "Or: each unit's calibrated greybox model file (no covariance, no noise: screening is then less exact)");
  learn->add_option("--set", l->set,
                    "greybox option key=value for the units' structure (calibrate --options-of greybox), or lot.KEY=value: "
                    "lot.variance_kept (0.99), lot.max_modes (12), lot.trim_alpha (0.0001), lot.max_loo_units (200)");
  learn->add_option("--screen-recordings", l->screen_recordings,
                    "The same units recorded on the programme a production line screens with (one per unit, same order): the "
                    "screening's null is calibrated on them (default: on the units' own recordings)");
  learn->add_option("--name", l->name, "The lot's name in the file");
  learn->add_option("--package-tau-s", l->package_tau_s,
                    "The members' chamber-to-probe lag, s (a calibration sees the probe only; the design's programme is in chamber temperatures)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e5));
  learn->add_option("--out", l->out, "Lot file to write (JSON, format gyrosid-prior/1 with a population)")->required();
  learn->footer(
      "Example: gyrosid lot learn --recordings units/*.csv --set shupe=true --out lot.json\n"
      "         mpirun -np 2 gyrosid-mpi lot learn ...        (the units calibrated across processes; the same bytes)\n"
      "         gyrosid design --prior lot.json --budget-min 15 --out d/      (the shortest programme for a unit of the lot)\n"
      "The population: each unit's grey-box coordinates (bias values, the scale-factor surface's nodes, Shupe, ...)\n"
      "as a Gaussian whose covariance is a few principal modes plus an isotropic rest (probabilistic PCA); the white\n"
      "noise log-normal across units; the leave-one-out distances of the units calibrate the screening's null. Units the\n"
      "others do not hold are left out (lot.trim_alpha) and named. The file is a prior over sensors (docs/prior_format.md):\n"
      "its members are the population's unscented points in its modes, for design --prior.");
  learn->add_flag("--resume", l->resume,
                  "Continue a killed run from its checkpoint beside --out (the units calibrated so far; same inputs and options): "
                  "it ends with the same bytes as an uninterrupted run");
  learn->callback([l, learn, &action] {
    l->command = learn;
    action = [l] { run_learn(*l); };
  });

  auto s = std::make_shared<LotScreenCommand>();
  CLI::App* screen = lot->add_subcommand("screen", "Does a unit belong to the lot? p-value, verdict and what is out of family");
  screen->add_option("--prior", s->prior, "Lot file (gyrosid lot learn)")->required();
  screen->add_option("--recording", s->recordings,
                     "The unit's recording, calibrated here with the lot's structure; or several units' (each screened on its own)")
      ->required();
  screen->add_option("--alpha", s->alpha, "False-alarm rate: out of family when p < alpha")->capture_default_str()->check(CLI::Range(1e-12, 0.5));
  screen->add_option("--out", s->out,
                     "Output directory: screen.json (out_of_family, p_value, reasons, contributions); for several recordings, "
                     "<stem>/screen.json per unit and screens.csv (a row per unit)")
      ->required();
  screen->add_flag("--resume", s->resume, "Continue a killed screening from its checkpoint in --out (the units calibrated so far)");
  screen->footer(
      "Example: gyrosid lot screen --prior lot.json --recording unit_0042.csv --out screen_0042/\n"
      "         mpirun -np 2 gyrosid-mpi lot screen --prior lot.json --recording units/*.csv --out screens/\n"
      "The statistic: the unit's Mahalanobis distance from the lot (with its own estimation covariance), referred to\n"
      "the lot's leave-one-out null; and its white noise against the lot's. Bonferroni over the two: the false-alarm\n"
      "rate is at most alpha. Reasons split the distance over terms and surface regions.");
  screen->callback([s, screen, &action] {
    s->command = screen;
    action = [s] { run_screen(*s); };
  });
}

}  // namespace gyrosid::cli
