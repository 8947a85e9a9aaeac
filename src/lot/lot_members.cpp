#include "lot/lot_members.h"

#include <Eigen/QR>

#include <cmath>

#include "core/format.h"
#include "core/units.h"
#include "sensor/sensor_prior.h"

namespace gyrosid {
namespace {

constexpr double kReferenceC = 25.0;

// The polynomial sum c_i (T - 25)^i through the bias values at the lot's nodes.
std::vector<double> bias_polynomial_dph(const GreyboxOptions& o, const Eigen::VectorXd& values) {
  const std::vector<double> nodes = greybox_bias_nodes_c(o);
  const auto m = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd v(m, m);
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = 0; j < m; ++j) v(i, j) = std::pow(nodes[static_cast<std::size_t>(i)] - kReferenceC, static_cast<double>(j));
  }
  const Eigen::VectorXd c = v.colPivHouseholderQr().solve(values);
  return std::vector<double>(c.data(), c.data() + c.size());
}

}  // namespace

std::string LotMemberOptions::validate() const {
  if (!(package_tau_s >= 0.0)) return "package_tau_s must be >= 0";
  if (max_modes < 0) return "max_modes must be >= 0";
  return "";
}

nlohmann::json lot_sensor_config(const LotModel& lot, const Eigen::VectorXd& theta, const std::string& name, const LotMemberOptions& o) {
  const GreyboxOptions& s = lot.structure;
  const GreyboxThetaLayout at(s);
  const std::vector<double> bias = bias_polynomial_dph(s, at.bias.of(theta));
  const auto nt = s.surface_temperatures_c.size(), nw = s.surface_rates_dps.size();
  std::vector<std::vector<double>> surface(nt, std::vector<double>(nw));
  Eigen::Index node = 0;
  for (auto& row : surface) {
    for (double& v : row) v = theta(at.surface.at(node++));
  }
  nlohmann::json temperature_coefficients = std::vector<double>(bias.begin(), bias.end());
  temperature_coefficients[0] = 0.0;  // the constant is constant_dph
  nlohmann::json sensor = {
      {"kind", "gyro"},
      {"name", name},
      {"bias", {{"constant_dph", bias[0]}, {"temperature", {{"reference_c", kReferenceC}, {"coefficients_dph", temperature_coefficients}}}}},
      {"scale_factor",
       {{"surface", {{"temperatures_c", s.surface_temperatures_c}, {"rates_dps", s.surface_rates_dps}, {"error_ppm", surface}, {"outside", "clamp"}}}}},
      {"noise", {{"white_dph_at_1hz", lot.noise_units > 0 ? std::exp(lot.log_noise_mean) : 0.0}}},
      {"thermal", {{"tau_s", o.package_tau_s}, {"delay_s", 0.0}, {"coil_tau_s", 0.0}}},
      {"range_dps", 500.0}};
  if (s.shupe) sensor["shupe_dph_per_c_per_min"] = theta(at.shupe.offset);
  if (s.asymmetry) sensor["scale_factor"]["asymmetry_ppm"] = theta(at.asymmetry.offset);
  if (s.g_sensitivity) {
    std::vector<double> g;
    for (int i = 0; i < 3; ++i) g.push_back(theta(at.g_sensitivity.at(i)) * units::kStandardGravity);
    sensor["g_sensitivity_dph_per_g"] = g;
  }
  if (s.thermal_lag) sensor["thermal"]["coil_tau_s"] = std::max(0.0, theta(at.lag.offset));
  return sensor;
}

nlohmann::json lot_members(const LotModel& lot, const LotMemberOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("lot members: ", p);
  const Eigen::Index k = std::min<Eigen::Index>(lot.modes.cols(), o.max_modes);
  const double spread = std::sqrt(static_cast<double>(k + 1));
  nlohmann::json members = nlohmann::json::array();
  members.push_back({{"sensor", lot_sensor_config(lot, lot.mean, "lot mean", o)}, {"weight", 1.0 / static_cast<double>(k + 1)}});
  for (Eigen::Index i = 0; i < k; ++i) {
    const Eigen::VectorXd m = lot.scale.cwiseProduct(lot.modes.col(i));
    for (int sign : {+1, -1}) {
      members.push_back({{"sensor", lot_sensor_config(lot, lot.mean + sign * spread * m, str_cat("lot mode ", i + 1, sign > 0 ? " +" : " -"), o)},
                         {"weight", 0.5 / static_cast<double>(k + 1)}});
    }
  }
  return members;
}

nlohmann::json lot_prior_file(const LotModel& lot, const std::string& name, const LotMemberOptions& options) {
  return {{"format", kSensorPriorFormat},
          {"name", name.empty() ? str_cat("lot of ", lot.unit_names.size(), " units") : name},
          {"members", lot_members(lot, options)},
          {"population", lot.to_json()}};
}

}  // namespace gyrosid
