#include "pipeline/lot_jobs.h"

#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>

#include "core/atomic_file.h"
#include "core/checkpoint.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "lot/lot_unit.h"
#include "report/lot_report.h"
#include "solvers/calibrate.h"

namespace gyrosid {
namespace {

void list_text(std::ostream& text, const char* what, const std::vector<std::string>& items) {
  text << what << " [";
  for (const auto& item : items) text << item << '\n';
  text << "]\n";
}

// The conditional tests' null (lot_model.h): the null's units' recordings, each refitted with the lot learned
// without it.
void add_conditional_nulls(LotModel& lot, const LotLearnOptions& o, const LotUnits& units, Checkpoint& checkpoint) {
  const std::vector<std::string>& probes = o.screen_recordings.empty() ? o.recordings : o.screen_recordings;
  std::vector<std::string> paths;
  for (std::size_t u : lot.null_units) paths.push_back(probes[u]);
  set_conditional_nulls(lot, conditional_scores(paths, lot, "lot learn: the conditional tests' null", &checkpoint, "conditional",
                                                [&](std::size_t k) { return lot_without(lot, units, lot.null_units[k], o.lot); }));
}

}  // namespace

void LotLearnOptions::set(const OptionMap& options) {
  OptionMap own;
  for (const auto& [key, value] : options) {
    if (key.rfind("lot.", 0) == 0) {
      own[key.substr(4)] = value;
    } else {
      structure[key] = value;
    }
  }
  lot.table().apply(own);
}

std::string LotLearnOptions::validate() const {
  if (recordings.empty() == models.empty()) return "give exactly one of --recordings (each unit calibrated here) or --models (greybox model files)";
  if (!models.empty() && !structure.empty()) return "--set greybox options apply to --recordings; --models keep the structure they were calibrated with";
  if (!screen_recordings.empty() && screen_recordings.size() != (recordings.empty() ? models.size() : recordings.size())) {
    return str_cat("--screen-recordings: ", screen_recordings.size(), " screening recordings for ", recordings.size() + models.size(),
                   " units; give one per unit, in the same order");
  }
  if (out.empty()) return "--out is required (the lot file to write)";
  if (auto problem = lot.validate(); !problem.empty()) return "lot." + problem;
  return members.validate();
}

std::string LotLearnOptions::fingerprint() const {
  std::ostringstream text;
  text << std::setprecision(17);
  list_text(text, "recordings", recordings);
  list_text(text, "models", models);
  list_text(text, "screen_recordings", screen_recordings);
  for (const auto& [key, value] : structure) text << key << '=' << value << '\n';
  text << lot.variance_kept << ' ' << lot.max_modes << ' ' << lot.trim_alpha << ' ' << lot.max_loo_units << '\n'
       << name << '\n' << members.package_tau_s << ' ' << members.max_modes;
  std::vector<std::string> files = recordings;
  files.insert(files.end(), models.begin(), models.end());
  files.insert(files.end(), screen_recordings.begin(), screen_recordings.end());
  return digest(text.str() + file_digests(files));
}

LotLearnResult run_lot_learn(const LotLearnOptions& o) {
  if (auto problem = o.validate(); !problem.empty()) fail(problem);
  // The units' calibrations are saved batch by batch beside the lot file; resume continues a killed run.
  const std::filesystem::path dir = o.out.parent_path().empty() ? std::filesystem::path(".") : o.out.parent_path();
  std::filesystem::create_directories(dir);
  Checkpoint checkpoint = checkpoint_in(dir, o.out.filename().string(), o.fingerprint(), o.resume);
  OptionMap structure = o.structure;
  const GreyboxOptions greybox = greybox_options(structure);
  std::unique_ptr<LotUnits> units;
  if (o.models.empty()) units = std::make_unique<CalibratedUnits>(calibrate_units(o.recordings, greybox, "lot learn: calibrating the units", &checkpoint));
  else units = std::make_unique<LotUnitsInMemory>(units_of_models(o.models, structure));
  progress_note(str_cat("lot learn: the population of ", units->size(), " units"));
  std::optional<CalibratedUnits> screen_units;
  if (!o.screen_recordings.empty()) {
    screen_units = calibrate_units(o.screen_recordings, greybox, "lot learn: the units' screening recordings", &checkpoint, "screen_units");
  }
  LotLearnResult result;
  result.lot = learn_lot(*units, structure, o.lot, screen_units ? &*screen_units : nullptr);
  LotModel& lot = result.lot;
  if (!o.recordings.empty() && !single_coordinate_terms(lot.coordinates).empty()) add_conditional_nulls(lot, o, *units, checkpoint);
  result.file = lot_prior_file(lot, o.name, o.members);
  write_file_atomic(o.out, result.file.dump(1) + "\n");
  checkpoint.finish();
  const double rest = lot.residual_variance * static_cast<double>(lot.coordinates.size() - static_cast<std::size_t>(lot.modes.cols()));
  result.mode_share = lot.mode_variance.sum() / (lot.mode_variance.sum() + rest);
  return result;
}

std::string LotScreenOptions::validate() const {
  if (prior.empty()) return "--prior is required (a lot file of gyrosid lot learn)";
  if (recordings.empty()) return "--recording is required";
  if (out.empty()) return "--out DIR is required";
  return screen.validate();
}

std::string LotScreenOptions::fingerprint() const {
  std::ostringstream text;
  text << std::setprecision(17) << prior << '\n';
  list_text(text, "recordings", recordings);
  text << screen.alpha;
  std::vector<std::string> files = recordings;
  files.push_back(prior);
  return digest(text.str() + file_digests(files));
}

LotScreenResult run_lot_screen(const LotScreenOptions& o) {
  if (auto problem = o.validate(); !problem.empty()) fail(problem);
  const LotModel lot = load_lot(o.prior);
  const std::vector<std::filesystem::path> dirs = screen_dirs(o.out, o.recordings);
  std::filesystem::create_directories(o.out);
  Checkpoint checkpoint = checkpoint_in(o.out, "lot_screen", o.fingerprint(), o.resume);
  const CalibratedUnits units = calibrate_units(o.recordings, lot.structure, "lot screen: calibrating the units with the lot's structure", &checkpoint,
                                                "units", lot.conditional_terms.empty() ? nullptr : &lot);
  LotScreenResult result;
  std::string table = kScreensCsvHeader;
  for (std::size_t k = 0; k < units.size(); ++k) {
    const LotUnit unit = units.at(k);
    ScreenedUnit s{o.recordings[k], dirs[k], screen_unit(lot, unit, o.screen), unit.white_dph_at_1hz, {}};
    s.file = screen_json(s.result, s.recording, o.prior, o.screen.alpha, s.white_dph_at_1hz);
    std::filesystem::create_directories(s.dir);
    write_file_atomic(s.dir / "screen.json", s.file.dump(2) + "\n");
    table += screens_csv_row(s.result, s.recording, s.white_dph_at_1hz);
    result.out_of_family += s.result.out_of_family;
    ++result.screened;
    if (o.keep_in_family || s.result.out_of_family) result.units.push_back(std::move(s));
  }
  if (units.size() > 1) write_file_atomic(o.out / "screens.csv", table);
  checkpoint.finish();
  return result;
}

void take_lot_prior(CalibrationRequest& request, const LotModel& lot) {
  request.model = "greybox";
  request.options = lot.greybox_options;
  request.greybox_prior = std::make_shared<const GreyboxPrior>(lot.prior());
}

}  // namespace gyrosid
