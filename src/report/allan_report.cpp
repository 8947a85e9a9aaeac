#include "report/allan_report.h"

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

}  // namespace gyrosid
