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

namespace {

// theta is defined on the surface form only (a polynomial scale factor has no grid to compare units on).
void require_surface_form(const GreyboxOptions& o) {
  if (o.scale_factor != ScaleFactorForm::surface) fail("a grey-box prior needs the surface form of the scale factor (scale_factor=surface)");
}

}  // namespace

std::vector<GreyboxCoordinate> greybox_coordinates(const GreyboxOptions& o) {
  require_surface_form(o);
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

GreyboxThetaLayout::GreyboxThetaLayout(const GreyboxOptions& o) {
  SpanPacker pack;
  bias = pack.take(o.bias_order + 1);
  surface = pack.take(static_cast<Eigen::Index>(o.surface_temperatures_c.size() * o.surface_rates_dps.size()));
  shupe = pack.take_if(o.shupe, 1);
  asymmetry = pack.take_if(o.asymmetry, 1);
  g_sensitivity = pack.take_if(o.g_sensitivity, 3);
  lag = pack.take_if(o.thermal_lag, 1);
  size = pack.size();
}

Eigen::VectorXd greybox_theta(const GyroErrorModel& e, double lag_tau_s, const GreyboxOptions& o) {
  require_surface_form(o);
  const GreyboxThetaLayout at(o);
  Eigen::VectorXd theta(at.size);
  const std::vector<double> nodes = greybox_bias_nodes_c(o);
  for (std::size_t j = 0; j < nodes.size(); ++j) theta(at.bias.at(static_cast<Eigen::Index>(j))) = units::radps_to_dph(e.bias_radps + e.bias_temperature_radps(nodes[j]));
  Eigen::Index node = 0;
  for (double t : o.surface_temperatures_c) {
    for (double w : o.surface_rates_dps) {
      theta(at.surface.at(node++)) = e.scale_factor_surface ? units::ratio_to_ppm((*e.scale_factor_surface)(t, units::dps_to_radps(w)).value) : 0.0;
    }
  }
  if (o.shupe) theta(at.shupe.offset) = units::radps_to_dph(e.shupe_rad_per_c) / units::kSecondsPerMinute;
  if (o.asymmetry) theta(at.asymmetry.offset) = units::ratio_to_ppm(e.scale_factor_asymmetry);
  if (o.g_sensitivity) at.g_sensitivity.of(theta) = e.g_sensitivity.unaryExpr([](double g) { return units::radps_to_dph(g); });
  if (o.thermal_lag) theta(at.lag.offset) = lag_tau_s;
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
