#include "report/allan_report.h"

#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "report/plots.h"

namespace gyrosid {

AllanReport write_allan(const std::filesystem::path& dir, const std::vector<double>& rate_dph, double dt_s,
                        const AllanOptions& options, const std::string& title, nlohmann::json provenance) {
  AllanReport r;
  r.curve = overlapping_allan_deviation(rate_dph, dt_s, options);
  r.fit = fit_allan(r.curve);
  write_file_atomic(dir / "allan.csv", [&](std::ostream& out) {
    out << "tau_s,adev_dph,ci_low_dph,ci_high_dph,edf,terms,noise_alpha\n";
    for (const auto& p : r.curve) {
      out << format_number(p.tau_s) << ',' << format_number(p.adev) << ',' << format_number(p.ci_low) << ','
          << format_number(p.ci_high) << ',' << format_number(p.edf) << ',' << p.terms << ',' << p.alpha << '\n';
    }
  });
  // Coefficients from deg/h-based units: Q (deg/h)s = arcsec; N (deg/h)sqrt(s) / 60 = deg/sqrt(h);
  // K (deg/h)/sqrt(s) * 60 = (deg/h)/sqrt(h); R (deg/h)/s * 3600 = (deg/h)/h.
  nlohmann::json j = std::move(provenance);
  j["sample_interval_s"] = dt_s;
  j["samples"] = rate_dph.size();
  j["confidence"] = options.confidence;
  j["coefficients"] = {
      {"quantization_arcsec", r.fit.quantization},
      {"arw_deg_rt_h", r.fit.angle_random_walk / 60.0},
      {"white_dph_at_1hz", r.fit.angle_random_walk},
      {"bias_instability_dph", r.fit.bias_instability},
      {"rrw_dph_rt_h", r.fit.rate_random_walk * 60.0},
      {"rate_ramp_dph_per_h", r.fit.rate_ramp * 3600.0},
  };
  j["fit_relative_rms_residual"] = r.fit.relative_rms_residual;
  write_file_atomic(dir / "allan.json", j.dump(2) + "\n");
  plot_allan(dir / "allan.png", r.curve, r.fit, title, "deg/h");
  return r;
}

void write_kalibr_noise_yaml(const std::filesystem::path& path, const AllanCoefficients& fit, double update_rate_hz,
                             const std::string& source) {
  constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;
  // fit is in deg/h-based units: angle_random_walk in (deg/h) sqrt(s), rate_random_walk in (deg/h)/sqrt(s).
  const double noise_density = fit.angle_random_walk / 3600.0 * kRadPerDeg;   // rad/s * sqrt(s) = rad/s/sqrt(Hz)
  const double random_walk = fit.rate_random_walk / 3600.0 * kRadPerDeg;      // rad/s / sqrt(s) = rad/s^2/sqrt(Hz)
  std::ostringstream out;
  out << "# Kalibr IMU noise model (imu.yaml), gyro terms from gyrosid's Allan fit of " << source << "\n"
      << "# Continuous-time densities, as Kalibr expects; the discrete white-noise sigma at update_rate is\n"
      << "# gyroscope_noise_density * sqrt(update_rate), the discrete bias step gyroscope_random_walk / sqrt(update_rate).\n"
      << "# Accelerometer terms are not written: this recording characterises the gyro only.\n"
      << "#Gyroscopes\n"
      << "gyroscope_noise_density: " << format_number(noise_density) << "  # rad/s/sqrt(Hz) = N "
      << format_significant(fit.angle_random_walk / 60.0) << " deg/sqrt(h) * (pi/180) / 60\n"
      << "gyroscope_random_walk: " << format_number(random_walk) << "  # rad/s^2/sqrt(Hz) = K "
      << format_significant(fit.rate_random_walk * 60.0) << " (deg/h)/sqrt(h) * (pi/180) / 3600 / 60\n"
      << "update_rate: " << format_number(update_rate_hz) << "  # Hz, the recording's sample rate\n";
  write_file_atomic(path, out.str());
}

}  // namespace gyrosid
