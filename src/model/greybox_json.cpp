// The grey-box model's parameters in a model file: the GyroErrorModel's coefficients (SI) and the lag; a fit
// under a prior adds "posterior": the WeightPosterior's fields (weight_posterior.h) with the terms, their
// scaling and the coefficients (the posterior mean) it is over. Files without it load as before.
#include <cmath>

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

nlohmann::json posterior_json(const GreyboxPosterior& p) {
  nlohmann::json j = p.weights.to_json();
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : p.terms) terms.push_back(t.to_json());
  j["terms"] = terms;
  j["scaling"] = p.scaling.to_json();
  j["mean"] = std::vector<double>(p.coefficients.data(), p.coefficients.data() + p.coefficients.size());
  return j;
}

GreyboxPosterior posterior_of(const nlohmann::json& j) {
  GreyboxPosterior p;
  for (const auto& t : j.at("terms")) p.terms.push_back(Term::from_json(t));
  p.scaling = TermScaling::from_json(j.at("scaling"));
  const auto mean = j.at("mean").get<std::vector<double>>();
  p.coefficients = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  if (!p.coefficients.allFinite()) fail("greybox model: the posterior's mean has non-finite values");
  p.weights = WeightPosterior::from_json(j, total_columns(p.terms), "greybox model");
  return p;
}

// The posterior's mean against the error model's parameters, which hold the same coefficients: h(x)' c =
// predict(x) at rates and temperatures spanning the fit's scaling (extra inputs at 1) - else the file was
// edited in one place and not the other.
void check_posterior_mean(const GreyboxModel& m) {
  const GreyboxPosterior& p = *m.coefficient_posterior();
  Eigen::MatrixXd x = Eigen::MatrixXd::Ones(12, static_cast<Eigen::Index>(m.features().size()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    x(i, 0) = p.scaling.rate_scale_radps * (i % 4 - 1.5) / 1.5;
    x(i, 1) = p.scaling.t_ref_c + p.scaling.t_scale_c * static_cast<double>(i / 4 - 1);
  }
  const Eigen::VectorXd linear = m.regressors(x) * p.coefficients;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double predicted = m.predict(x.row(i).eval().data());
    if (!(std::abs(linear(i) - predicted) <= 1e-9 * (std::abs(x(i, 0)) + std::abs(predicted)))) {
      fail("greybox model: the posterior's mean gives ", linear(i), " rad/s where the parameters give ", predicted, " at ", x(i, 0),
           " rad/s, ", x(i, 1), " C: they disagree");
    }
  }
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
  if (posterior_) j["posterior"] = posterior_json(*posterior_);
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
  std::optional<GreyboxPosterior> posterior;
  if (j.contains("posterior")) posterior = posterior_of(j.at("posterior"));
  auto model = std::make_unique<GreyboxModel>(std::move(features), std::move(e), j.value("lag_tau_s", 0.0), std::move(posterior));
  if (model->coefficient_posterior()) check_posterior_mean(*model);
  return model;
}

}  // namespace gyrosid
