#include "nav/cof_report.h"

#include <cmath>
#include <cstring>

#include "core/config.h"
#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "sensor/sensor_config.h"

namespace gyrosid::nav {

FlightTrajectory load_flight(const std::string& name, double rate_hz) {
  const auto ends_with = [&](const char* s) { return name.size() > std::strlen(s) && name.ends_with(s); };
  if (ends_with(".csv")) return load_flight_csv(name);
  if (ends_with(".yaml") || ends_with(".yml") || name.rfind("builtin:", 0) == 0) {
    return generate_flight(load_flight_profile(ConfigNode::load(name)), rate_hz);
  }
  return generate_flight(builtin_flight(name), rate_hz);
}

CofReport evaluate_criterion_of_fit(const CofRequest& r) {
  std::unique_ptr<CalibrationModel> model;
  CompensationMode mode = CompensationMode::model;
  if (r.model == "none") mode = CompensationMode::none;
  else if (r.model == "truth") mode = CompensationMode::truth;
  else model = load_model(r.model);
  return score_flight(load_flight(r.trajectory, r.rate_hz), as_triad(load_sensor_file(r.sensor)), model.get(), mode, r);
}

CofReport score_flight(FlightTrajectory flight, const TriadSensor& sensor, const CalibrationModel* model,
                       CompensationMode mode, const CofRequest& r) {
  CofReport report;
  report.flight = std::move(flight);
  const CofEvaluator cof(report.flight, sensor, model, r.options);
  report.reference = cof.reference_path();

  report.run = cof.run(mode, false, r.seed, true);
  report.uncompensated = cof.run(CompensationMode::none, false, r.seed, true);
  const Eigen::Vector3d parts = cof.decompose(report.run.error_ned);
  const double hours = cof.duration_s() / 3600.0;
  const double drift_basis = std::isnan(report.run.error_after_1h_m) ? report.run.end_error_m / hours : report.run.error_after_1h_m;
  nlohmann::json j = {
      {"trajectory", r.trajectory},
      {"model", r.model},
      {"sensor", r.sensor},
      {"duration_s", cof.duration_s()},
      {"rate_hz", r.rate_hz},
      {"start_temp_c", r.options.start_temp_c},
      {"thermal_delay_s", r.options.thermal_delay_s},
      {"temperature_probe", std::string(to_string(r.options.probe))},
      {"rate_limit_dps", r.options.clip_rate_dps},
      {"rates", r.options.scale_rates ? "scaled" : "clipped"},
      {"max_rate_dps", cof.max_abs_rate_dps()},
      {"clipped_samples", cof.clipped_samples()},
      {"end_error_m", report.run.end_error_m},
      {"error_ned_m", {report.run.error_ned.x(), report.run.error_ned.y(), report.run.error_ned.z()}},
      {"along_track_m", parts.x()},
      {"cross_track_m", {parts.y(), parts.z()}},
      {"uncompensated_end_error_m", report.uncompensated.end_error_m},
      {"drift_m_per_h", drift_basis},
      {"drift_nmi_per_h", drift_basis / 1852.0},
      {"seed", r.seed}};
  auto dph = [](const Eigen::Vector3d& v) { return std::vector<double>{units::radps_to_dph(v.x()), units::radps_to_dph(v.y()), units::radps_to_dph(v.z())}; };
  j["residual_rate_dph"] = {{"mean", dph(report.run.residual_mean)}, {"rms", dph(report.run.residual_rms)}};
  if (!std::isnan(report.run.error_after_1h_m)) j["error_after_1h_m"] = report.run.error_after_1h_m;
  if (!std::isnan(report.uncompensated.error_after_1h_m)) j["uncompensated_error_after_1h_m"] = report.uncompensated.error_after_1h_m;

  if (r.monte_carlo) {
    // New noise every run; the thesis's reference runs beside it: only the white noise (no sensor error,
    // no compensation) and a constant bias equal to the noise's 1-Hz sigma (s5.5).
    const std::uint64_t base = r.seed;
    report.mc = monte_carlo([&](int i) {
      return cof.decompose(cof.run(mode, true, base ^ hash_name("mc/" + std::to_string(i)), false).error_ned);
    }, r.mc);
    j["monte_carlo"] = report.mc->to_json();
    const double sigma = sensor.gyros[0].noise.arw_rad_rt_s;  // white-noise sigma at 1 Hz, rad/s
    if (sigma > 0) {
      MonteCarloOptions ref = r.mc;
      const MonteCarloResult just_noise = monte_carlo([&](int i) {
        return cof.decompose(cof.run_reference(sigma, 0.0, base ^ hash_name("noise/" + std::to_string(i))).error_ned);
      }, ref);
      const CofRun bias = cof.run_reference(0.0, sigma, base);
      j["monte_carlo"]["reference_just_noise"] = just_noise.to_json();
      j["monte_carlo"]["reference_bias"] = {{"bias_dph", units::radps_to_dph(sigma)}, {"end_error_m", bias.end_error_m}};
      const double inc2 = report.mc->sigma_m * report.mc->sigma_m - just_noise.sigma_m * just_noise.sigma_m;
      j["monte_carlo"]["sigma_increase_m"] = inc2 > 0 ? std::sqrt(inc2) : 0.0;  // thesis eq 5.2
    }
  }
  report.summary = j;
  return report;
}

}  // namespace gyrosid::nav
