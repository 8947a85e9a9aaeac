// The grey-box model's parameters in a model file: the GyroErrorModel's coefficients (SI) and the lag.
#include "core/error.h"
#include "model/greybox_model.h"

namespace gyrosid {
namespace {

nlohmann::json polynomial_json(const Polynomial& p) { return {{"reference", p.reference}, {"coefficients", p.coefficients}}; }
Polynomial polynomial_of(const nlohmann::json& j) {
  return {j.at("coefficients").get<std::vector<double>>(), j.at("reference").get<double>()};
}

nlohmann::json surface_json(const SplineSurface& s) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < s.values().rows(); ++i) {
    std::vector<double> row;
    for (Eigen::Index k = 0; k < s.values().cols(); ++k) row.push_back(s.values()(i, k));
    rows.push_back(row);
  }
  return {{"temperatures_c", s.x()}, {"rates_radps", s.y()}, {"values", rows}, {"outside", to_string(s.outside())}};
}

SplineSurface surface_of(const nlohmann::json& s) {
  const auto rows = s.at("values").get<std::vector<std::vector<double>>>();
  const auto x = s.at("temperatures_c").get<std::vector<double>>(), y = s.at("rates_radps").get<std::vector<double>>();
  Eigen::MatrixXd v(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(y.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != y.size()) fail("greybox model: surface row ", i, " has ", rows[i].size(), " values");
    for (std::size_t k = 0; k < y.size(); ++k) v(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k];
  }
  return SplineSurface(x, y, v, parse_enum<OutsideGridPolicy>(s.at("outside").get<std::string>()));
}

}  // namespace

nlohmann::json GreyboxModel::parameters_json() const {
  const GyroErrorModel& e = errors_;
  nlohmann::json j = {{"bias_radps", e.bias_radps},
                      {"bias_temperature_radps", polynomial_json(e.bias_temperature_radps)},
                      {"scale_factor_temperature", polynomial_json(e.scale_factor_temperature)},
                      {"scale_factor_rate", polynomial_json(e.scale_factor_rate)},
                      {"scale_factor_asymmetry", e.scale_factor_asymmetry},
                      {"shupe_rad_per_c", e.shupe_rad_per_c},
                      {"g_sensitivity", {e.g_sensitivity.x(), e.g_sensitivity.y(), e.g_sensitivity.z()}},
                      {"lag_tau_s", lag_tau_s_}};
  if (e.scale_factor_surface) j["scale_factor_surface"] = surface_json(*e.scale_factor_surface);
  return j;
}

std::unique_ptr<GreyboxModel> GreyboxModel::from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                      ModelTarget target) {
  if (target != ModelTarget::error) fail("greybox model: target must be error");
  GyroErrorModel e;
  e.bias_radps = j.at("bias_radps").get<double>();
  e.bias_temperature_radps = polynomial_of(j.at("bias_temperature_radps"));
  e.scale_factor_temperature = polynomial_of(j.at("scale_factor_temperature"));
  e.scale_factor_rate = polynomial_of(j.at("scale_factor_rate"));
  e.scale_factor_asymmetry = j.at("scale_factor_asymmetry").get<double>();
  e.shupe_rad_per_c = j.at("shupe_rad_per_c").get<double>();
  const auto g = j.at("g_sensitivity").get<std::vector<double>>();
  if (g.size() != 3) fail("greybox model: g_sensitivity needs 3 values");
  e.g_sensitivity = Eigen::Vector3d(g[0], g[1], g[2]);
  if (j.contains("scale_factor_surface")) e.scale_factor_surface = surface_of(j.at("scale_factor_surface"));
  return std::make_unique<GreyboxModel>(std::move(features), std::move(e), j.value("lag_tau_s", 0.0));
}

}  // namespace gyrosid
