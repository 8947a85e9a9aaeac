// gyrosid allan: overlapping Allan deviation of a recording column, fitted noise coefficients, plot.
#include <algorithm>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "cli/common.h"
#include "core/error.h"
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
};

void run_allan(const AllanCommandOptions& o) {
  if (auto p = o.allan.validate(); !p.empty()) fail("--points-per-decade/--max-tau-fraction/--confidence: ", p);
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
  const AllanReport r = write_allan(o.out, rate, dt, o.allan, title, provenance);
  std::cout << "wrote " << o.out << "/allan.csv, allan.json, allan.png (" << r.curve.size() << " averaging times)\n"
            << "  N  = " << r.fit.angle_random_walk / 60.0 << " deg/sqrt(h)\n"
            << "  B  = " << r.fit.bias_instability << " deg/h\n"
            << "  K  = " << r.fit.rate_random_walk * 60.0 << " (deg/h)/sqrt(h)\n"
            << "  Q  = " << r.fit.quantization << " arcsec\n"
            << "  R  = " << r.fit.rate_ramp * 3600.0 << " (deg/h)/h\n";
  if (!o.kalibr.empty()) {
    write_kalibr_noise_yaml(o.kalibr, r.fit, 1.0 / dt, o.recording + ", column " + series.column);
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
  cmd->add_option("--confidence", o->allan.confidence, "Two-sided confidence of the intervals")->capture_default_str();
  cmd->add_option("--out", o->out, "Output directory: allan.csv, allan.json, allan.png")->required();
  cmd->add_option("--kalibr", o->kalibr, "Also write a Kalibr imu.yaml with the gyro noise density and random walk "
                                         "(continuous-time units; the conversion is written in the file)");
  cmd->footer(
      "The fit: sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (2ln2/pi)B^2 + K^2 tau/3 + R^2 tau^2/2 (IEEE Std 952),\n"
      "non-negative least squares on relative residuals weighted by the chi-square degrees of freedom.\n"
      "A recording that is not uniformly sampled is refused (resample it first).\n"
      "Example: gyrosid allan --recording static.csv --column gyro_dps --subtract ref_rate_dps --out allan/");
  cmd->callback([o, &action] { action = [o] { run_allan(*o); }; });
}

}  // namespace gyrosid::cli
