// gyrosid lot: a production lot - learn the population of a gyro type from calibrated units (lot/lot_model.h)
// and screen a unit against it (lot/screen.h). `gyrosid calibrate --prior lot.json` fits a new unit with it.
// The jobs are pipeline/lot_jobs.h; this file parses and prints.
#include <cmath>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/format.h"
#include "pipeline/lot_jobs.h"

namespace gyrosid::cli {
namespace {

struct LotLearnCommand {
  LotLearnOptions options;
  std::vector<std::string> set;
  std::string out;
};

struct LotScreenCommand {
  LotScreenOptions options;
  std::string out;
};

void run_learn(LotLearnCommand& c) {
  LotLearnOptions& o = c.options;
  o.out = c.out;
  o.set(parse_options(c.set));
  const LotLearnResult r = run_lot_learn(o);
  const LotModel& lot = r.lot;
  std::cout << "wrote " << c.out << ": " << lot.unit_names.size() << " units, " << lot.coordinates.size() << " coordinates, " << lot.modes.cols()
            << " modes (" << format_significant(100.0 * r.mode_share, 3) << " % of the standardised variance)";
  if (lot.noise_units > 0) std::cout << ", white noise " << format_significant(std::exp(lot.log_noise_mean), 3) << " dph at 1 Hz x/ " << format_significant(std::exp(lot.log_noise_sd), 3);
  std::cout << "\n";
  if (!lot.left_out.empty()) std::cout << "left out as out of family (leave-one-out p < " << o.lot.trim_alpha << "): " << join(lot.left_out) << "\n";
}

void print_screen(const std::string& recording, const ScreenResult& r, double alpha) {
  std::cout << recording << ": " << (r.out_of_family ? "OUT OF FAMILY" : "in family") << " (p = " << format_significant(r.p_value, 3)
            << "; physics " << format_significant(r.p_physics, 3) << ", noise " << format_significant(r.p_noise, 3) << "; alpha " << alpha << ")\n";
  for (const auto& reason : r.reasons) std::cout << "  " << reason << "\n";
  if (!r.warning.empty()) std::cout << "warning: " << r.warning << "\n";
}

void run_screen(LotScreenCommand& c) {
  LotScreenOptions& o = c.options;
  o.out = c.out;
  o.keep_in_family = o.recordings.size() == 1;  // one unit is printed whole; of many, those out of family
  const LotScreenResult r = run_lot_screen(o);
  for (const ScreenedUnit& u : r.units) print_screen(u.recording, u.result, o.screen.alpha);
  if (r.screened == 1) {
    std::cout << "wrote " << (r.units.front().dir / "screen.json").string() << "\n";
  } else {
    std::cout << r.out_of_family << " of " << r.screened << " units out of family at alpha " << o.screen.alpha << "; wrote " << r.screened
              << " screen.json and " << (o.out / "screens.csv").string() << "\n";
  }
}

}  // namespace

void register_lot(CLI::App& app, Action& action) {
  CLI::App* lot = app.add_subcommand("lot", "A production lot: learn a gyro type's population from its units, screen a unit against it");
  lot->require_subcommand(1);
  auto l = std::make_shared<LotLearnCommand>();
  CLI::App* learn = lot->add_subcommand("learn", "Learn the lot's population (physics terms' mean and low-rank covariance, noise) from N units");
  learn->add_option("--recordings", l->options.recordings, "Each unit's recording (single gyro, with ref_rate_dps); each is calibrated with the greybox model");
  learn->add_option("--models", l->options.models, "Or: each unit's calibrated greybox model file (no covariance, no noise: screening is then less exact)");
  learn->add_option("--set", l->set,
                    "greybox option key=value for the units' structure (calibrate --options-of greybox), or lot.KEY=value: "
                    "lot.variance_kept (0.99), lot.max_modes (12), lot.trim_alpha (0.0001), lot.max_loo_units (200)");
  learn->add_option("--screen-recordings", l->options.screen_recordings,
                    "The same units recorded on the programme a production line screens with (one per unit, same order): the "
                    "screening's null is calibrated on them (default: on the units' own recordings)");
  learn->add_option("--name", l->options.name, "The lot's name in the file");
  learn->add_option("--package-tau-s", l->options.members.package_tau_s,
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
  learn->add_flag("--resume", l->options.resume,
                  "Continue a killed run from its checkpoint beside --out (the units calibrated so far; same inputs and options): "
                  "it ends with the same bytes as an uninterrupted run");
  learn->callback([l, &action] { action = [l] { run_learn(*l); }; });

  auto s = std::make_shared<LotScreenCommand>();
  CLI::App* screen = lot->add_subcommand("screen", "Does a unit belong to the lot? p-value, verdict and what is out of family");
  screen->add_option("--prior", s->options.prior, "Lot file (gyrosid lot learn)")->required();
  screen->add_option("--recording", s->options.recordings,
                     "The unit's recording, calibrated here with the lot's structure; or several units' (each screened on its own)")
      ->required();
  screen->add_option("--alpha", s->options.screen.alpha, "False-alarm rate: out of family when p < alpha")->capture_default_str()->check(CLI::Range(1e-12, 0.5));
  screen->add_option("--out", s->out,
                     "Output directory: screen.json (out_of_family, p_value, reasons, contributions); for several recordings, "
                     "<stem>/screen.json per unit and screens.csv (a row per unit)")
      ->required();
  screen->add_flag("--resume", s->options.resume, "Continue a killed screening from its checkpoint in --out (the units calibrated so far)");
  screen->footer(
      "Example: gyrosid lot screen --prior lot.json --recording unit_0042.csv --out screen_0042/\n"
      "         mpirun -np 2 gyrosid-mpi lot screen --prior lot.json --recording units/*.csv --out screens/\n"
      "The statistic: the unit's Mahalanobis distance from the lot (with its own estimation covariance), referred to\n"
      "the lot's leave-one-out null; and its white noise against the lot's. Bonferroni over the two: the false-alarm\n"
      "rate is at most alpha. Reasons split the distance over terms and surface regions.");
  screen->callback([s, &action] { action = [s] { run_screen(*s); }; });
}

}  // namespace gyrosid::cli
