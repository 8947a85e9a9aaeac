#include "model/greybox_prior.h"

#include <cmath>

#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

std::vector<double> greybox_bias_nodes_c(const GreyboxOptions& o) {
  const double lo = o.surface_temperatures_c.front(), hi = o.surface_temperatures_c.back();
  std::vector<double> nodes;
  for (int j = 0; j <= o.bias_order; ++j) nodes.push_back(o.bias_order == 0 ? 0.5 * (lo + hi) : lo + (hi - lo) * j / o.bias_order);
  return nodes;
}

std::vector<GreyboxCoordinate> greybox_coordinates(const GreyboxOptions& o) {
  if (o.scale_factor != ScaleFactorForm::surface) fail("a grey-box prior needs the surface form of the scale factor (scale_factor=surface)");
  std::vector<GreyboxCoordinate> c;
  for (double t : greybox_bias_nodes_c(o)) c.push_back({str_cat("bias(", format_number(t), " C)"), "bias", "dph", t, 0.0});
  for (double t : o.surface_temperatures_c) {
    for (double w : o.surface_rates_dps) c.push_back({str_cat("dSF(", format_number(t), " C, ", format_number(w), " dps)"), "surface", "ppm", t, w});
  }
  if (o.shupe) c.push_back({"shupe", "shupe", "dph_per_c_per_min", 0, 0});
  if (o.asymmetry) c.push_back({"asymmetry", "asymmetry", "ppm", 0, 0});
  if (o.g_sensitivity) {
    for (const char* a : {"g_x", "g_y", "g_z"}) c.push_back({a, "g_sensitivity", "dph_per_mps2", 0, 0});
  }
  if (o.thermal_lag) c.push_back({"lag_tau", "lag", "s", 0, 0});
  return c;
}

Eigen::VectorXd greybox_theta(const GyroErrorModel& e, double lag_tau_s, const GreyboxOptions& o) {
  const auto coordinates = greybox_coordinates(o);
  Eigen::VectorXd theta(static_cast<Eigen::Index>(coordinates.size()));
  Eigen::Index k = 0;
  for (double t : greybox_bias_nodes_c(o)) theta(k++) = units::radps_to_dph(e.bias_radps + e.bias_temperature_radps(t));
  for (double t : o.surface_temperatures_c) {
    for (double w : o.surface_rates_dps) {
      theta(k++) = e.scale_factor_surface ? units::ratio_to_ppm((*e.scale_factor_surface)(t, units::dps_to_radps(w)).value) : 0.0;
    }
  }
  if (o.shupe) theta(k++) = units::radps_to_dph(e.shupe_rad_per_c) / units::kSecondsPerMinute;
  if (o.asymmetry) theta(k++) = units::ratio_to_ppm(e.scale_factor_asymmetry);
  if (o.g_sensitivity) {
    for (int i = 0; i < 3; ++i) theta(k++) = units::radps_to_dph(e.g_sensitivity(i));
  }
  if (o.thermal_lag) theta(k++) = lag_tau_s;
  return theta;
}

std::string GreyboxPrior::validate(const GreyboxOptions& o) const {
  const auto p = static_cast<Eigen::Index>(greybox_coordinates(o).size());
  if (mean.size() != p || covariance.rows() != p || covariance.cols() != p) {
    return str_cat("the prior has ", mean.size(), " coordinates where the grey-box structure has ", p);
  }
  if (!mean.allFinite() || !covariance.allFinite()) return "the prior has non-finite numbers";
  if ((covariance - covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * covariance.cwiseAbs().maxCoeff()) return "the prior's covariance is not symmetric";
  for (Eigen::Index i = 0; i < p; ++i) {
    if (!(covariance(i, i) > 0.0)) return str_cat("the prior's variance of coordinate ", i, " is not positive");
  }
  return "";
}

}  // namespace gyrosid
