#include "cli/common.h"

#include <fstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/earth.h"
#include "core/error.h"
#include "core/units.h"
#include "report/plots.h"

namespace gyrosid::cli {

std::vector<double> rate_column_dph(const Recording& recording, const std::string& name) {
  const auto& column = recording.column(name);
  double scale = 0.0;
  if (name.size() > 4 && name.ends_with("_dps")) scale = units::kSecondsPerHour;
  if (name.size() > 4 && name.ends_with("_dph")) scale = 1.0;
  if (scale == 0.0) {
    fail(recording.source(), ": column '", name, "' is not a rate (its name must end in _dps or _dph)");
  }
  std::vector<double> out(column.size());
  for (std::size_t i = 0; i < column.size(); ++i) out[i] = column[i] * scale;
  return out;
}

const GyroSensor& representative_gyro(const SensorSpec& sensor) {
  if (const auto* g = std::get_if<GyroSensor>(&sensor)) return *g;
  return std::get<TriadSensor>(sensor).gyros[2];
}

std::function<double(double, double)> error_surface_dps(const GyroSensor& gyro) {
  return [&gyro](double temp_c, double rate_dps) {
    GyroEnvironment env;
    env.temp_c = temp_c;
    env.f_s = Eigen::Vector3d(0, 0, earth::normal_gravity(0.0));
    const double w = units::dps_to_radps(rate_dps);
    return units::radps_to_dps(gyro.errors.forward(w, env) - w);
  };
}

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

SurfaceGridSpec comparison_grid(const GyroSensor& truth, const std::vector<nlohmann::json>& trainings) {
  SurfaceGridSpec grid;
  if (truth.errors.scale_factor_surface) {
    grid.temp_min_c = truth.errors.scale_factor_surface->x().front();
    grid.temp_max_c = truth.errors.scale_factor_surface->x().back();
  }
  for (const auto& training : trainings) {
    const auto domain = training.value("/domain/temperature"_json_pointer, nlohmann::json());
    if (domain.is_array() && domain.size() == 2) {
      grid.temp_min_c = std::max(grid.temp_min_c, domain[0].get<double>());
      grid.temp_max_c = std::min(grid.temp_max_c, domain[1].get<double>());
    }
  }
  if (!(grid.temp_max_c > grid.temp_min_c)) fail("the models' training temperatures do not overlap the sensor's grid");
  return grid;
}

}  // namespace gyrosid::cli
