#include "report/cof_json.h"

#include <cmath>

#include "core/units.h"

namespace gyrosid {

namespace {

std::vector<double> dph(const Eigen::Vector3d& v) {
  return {units::radps_to_dph(v.x()), units::radps_to_dph(v.y()), units::radps_to_dph(v.z())};
}

}  // namespace

nlohmann::json cof_json(const nav::CofReport& r) {
  const nav::CofRequest& q = r.request;
  nlohmann::json j = {
      {"trajectory", q.trajectory},
      {"model", q.model},
      {"sensor", q.sensor},
      {"duration_s", r.duration_s()},
      {"rate_hz", q.rate_hz},
      {"start_temp_c", q.options.start_temp_c},
      {"thermal_delay_s", q.options.thermal_delay_s},
      {"temperature_probe", std::string(to_string(q.options.probe))},
      {"rate_limit_dps", q.options.clip_rate_dps},
      {"rates", q.options.scale_rates ? "scaled" : "clipped"},
      {"max_rate_dps", r.max_rate_dps},
      {"clipped_samples", r.clipped_samples},
      {"end_error_m", r.run.end_error_m},
      {"error_ned_m", {r.run.error_ned.x(), r.run.error_ned.y(), r.run.error_ned.z()}},
      {"along_track_m", r.decomposed.x()},
      {"cross_track_m", {r.decomposed.y(), r.decomposed.z()}},
      {"uncompensated_end_error_m", r.uncompensated.end_error_m},
      {"drift_m_per_h", r.drift_m_per_h},
      {"drift_nmi_per_h", r.drift_m_per_h / 1852.0},
      {"seed", q.seed},
      {"residual_rate_dph", {{"mean", dph(r.run.residual_mean)}, {"rms", dph(r.run.residual_rms)}}}};
  if (!std::isnan(r.run.error_after_1h_m)) j["error_after_1h_m"] = r.run.error_after_1h_m;
  if (!std::isnan(r.uncompensated.error_after_1h_m)) j["uncompensated_error_after_1h_m"] = r.uncompensated.error_after_1h_m;
  if (r.mc) {
    j["monte_carlo"] = r.mc->to_json();
    if (r.mc_reference) {
      const nav::CofReferenceRuns& ref = *r.mc_reference;
      j["monte_carlo"]["reference_just_noise"] = ref.just_noise.to_json();
      j["monte_carlo"]["reference_bias"] = {{"bias_dph", ref.bias_dph}, {"end_error_m", ref.bias_end_error_m}};
      j["monte_carlo"]["sigma_increase_m"] = ref.sigma_increase_m;
    }
  }
  return j;
}

}  // namespace gyrosid
