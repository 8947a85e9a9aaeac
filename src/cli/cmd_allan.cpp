// gyrosid allan: overlapping Allan deviation of a recording column, fitted noise coefficients, plot.
#include <algorithm>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "core/error.h"
#include "core/format.h"
#include "core/rate_series.h"
#include "report/allan_report.h"

namespace gyrosid::cli {
namespace {

struct AllanCommandOptions {
  std::string recording;
  std::string column = "gyro_dps";
  std::string subtract;
  std::string out;
  std::string kalibr;
  std::string axis;
  AllanOptions allan;
  NoiseIdOptions noise;
};

void run_allan(const AllanCommandOptions& o) {
  if (auto p = o.allan.validate(); !p.empty()) fail("--points-per-decade/--max-tau-fraction/--confidence: ", p);
  if (auto p = o.noise.validate(); !p.empty()) fail("--terms/--max-gauss-markov/--min-tau/--max-left-out-tau/--fit-tau-fraction: ", p);
  // Only the analysed column is held (core/rate_series.h); --axis reads a triad's gyro under the single-gyro names.
  const RateSeries series = read_rate_series(o.recording, {o.column, o.subtract, o.axis, "the Allan deviation"});
  const double dt = series.dt_s;
  const std::vector<double>& rate = series.rate_dph;
  if (series.reference_max_dph - series.reference_min_dph > 1.0) {
    // The Allan deviation of a rotating gyro's output is the table's motion, not the sensor's noise.
    std::cerr << "warning: " << o.recording << ": " << (o.axis.empty() ? "ref_rate_dps" : "ref_rate_" + o.axis + "_dps") << " varies over "
              << (series.reference_max_dph - series.reference_min_dph) / 3600.0 << " deg/s; the Allan deviation of " << series.column
              << " then measures the motion - pass --subtract ref_rate_dps to analyse the sensor's noise\n";
  }
  nlohmann::json provenance = {{"recording", o.recording}, {"column", series.column}, {"unit", "deg/h"}};
  if (!o.subtract.empty()) provenance["subtract"] = series.subtract;
  const std::string title = "Allan deviation of " + series.column + (o.subtract.empty() ? "" : " - " + series.subtract);
  NoiseIdOptions noise = o.noise;
  noise.confidence = o.allan.confidence;
  noise.robust = o.allan.robust;
  const AllanReport r = write_allan(o.out, rate, dt, o.allan, noise, title, provenance);
  const NoiseIdentification& n = r.noise;
  std::cout << "wrote " << o.out << "/allan.csv, allan.json, allan.png (" << r.curve.size() << " averaging times)\n"
            << "noise model " << n.structure.name() << " fitted from " << format_significant(n.fit_tau_low_s, 3) << " to "
            << format_significant(n.fit_tau_high_s, 3) << " s (chi2 " << format_significant(n.chi2, 3) << " on " << n.dof
            << " degrees of freedom, p " << format_significant(n.p_value, 2) << "), " << format_significant(100 * noise.confidence, 3)
            << " % intervals:\n";
  for (const auto& t : quoted_terms(n)) {
    std::cout << "  " << t.name << " = " << format_significant(t.value, 4) << " " << t.unit << "  [" << format_significant(t.low, 3) << ", "
              << format_significant(t.high, 3) << "]  " << t.meaning << "\n";
  }
  if (!n.left_out.empty()) std::cout << "note: " << n.left_out << "\n";
  if (!r.outside_band_note.empty()) std::cout << "note: " << r.outside_band_note << "\n";
  for (const auto& w : n.warnings) std::cerr << "warning: " << o.recording << ": " << w << "\n";
  if (!o.kalibr.empty()) {
    write_kalibr_noise_yaml(o.kalibr, n.model, 1.0 / dt, o.recording + ", column " + series.column);
    std::cout << "wrote " << o.kalibr << " (Kalibr IMU noise model, gyro terms in continuous-time units)\n";
  }
}

}  // namespace

void register_allan(CLI::App& app, Action& action) {
  auto o = std::make_shared<AllanCommandOptions>();
  CLI::App* cmd = app.add_subcommand("allan", "Overlapping Allan deviation of a recorded rate, with IEEE noise fit");
  cmd->add_option("--recording", o->recording, "Recording (gyrosid-recording/1 CSV), uniformly sampled")->required();
  cmd->add_option("--column", o->column, "Rate column to analyse (name ending in _dps or _dph)")->capture_default_str();
  cmd->add_option("--axis", o->axis, "Triad recordings: the gyro (x, y or z); gyro_dps and ref_rate_dps then name its columns");
  cmd->add_option("--subtract", o->subtract, "Rate column subtracted first, e.g. ref_rate_dps to remove the input");
  cmd->add_option("--points-per-decade", o->allan.points_per_decade, "Averaging times per decade")->capture_default_str();
  cmd->add_option("--max-tau-fraction", o->allan.max_tau_fraction, "Largest tau as a fraction of the record")
      ->capture_default_str();
  cmd->add_option("--confidence", o->allan.confidence, "Two-sided confidence of the curve's intervals and of the noise parameters'")
      ->capture_default_str();
  cmd->add_option("--terms", o->noise.terms, "Noise model: auto (chosen by chi2 + p ln n), or terms joined by '+' from Q (quantization), "
                                            "N (angle random walk), B (bias instability), K (rate random walk), R (rate ramp), GM (Gauss-Markov, repeat for more)")
      ->capture_default_str();
  cmd->add_option("--max-gauss-markov", o->noise.max_gauss_markov, "auto: at most this many Gauss-Markov terms")->capture_default_str();
  cmd->add_option("--min-tau", o->noise.min_tau_s, "Shortest tau the fit uses, s (0: detected - the taus a sensor filter distorts are left out)")
      ->capture_default_str();
  cmd->add_option("--max-left-out-tau", o->noise.max_left_out_tau_s, "The detection leaves out no tau above this, s")->capture_default_str();
  cmd->add_option("--fit-tau-fraction", o->noise.max_tau_fraction, "Longest tau the fit uses, as a fraction of the record")->capture_default_str();
  cmd->add_flag("--robust", o->allan.robust, "Robust Allan variances (bisquare M-scale of the second differences): for recordings with outliers");
  cmd->add_option("--out", o->out, "Output directory: allan.csv, allan.json, allan.png")->required();
  cmd->add_option("--kalibr", o->kalibr, "Also write a Kalibr imu.yaml with the gyro noise density and random walk "
                                         "(continuous-time units; the conversion is written in the file)");
  cmd->footer(
      "The model: sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (2ln2/pi)B^2 + K^2 tau/3 + R^2 tau^2/2 + Gauss-Markov terms (IEEE Std 952),\n"
      "fitted to the Allan variances at octave taus by generalised least squares weighted by their exact covariance under\n"
      "the model (iterated); the terms chosen by chi2 + p ln(samples); intervals from the fit's covariance. The shortest\n"
      "taus are left out while a C test finds them inconsistent with the rest (a sensor's anti-alias filter), and said so.\n"
      "allan.csv gains fit_dph (the fitted total at each tau); allan.json the terms with intervals, fit_band_s, warnings.\n"
      "A recording that is not uniformly sampled is refused (resample it first).\n"
      "Example: gyrosid allan --recording static.csv --column gyro_dps --subtract ref_rate_dps --out allan/");
  cmd->callback([o, &action] { action = [o] { run_allan(*o); }; });
}

}  // namespace gyrosid::cli
