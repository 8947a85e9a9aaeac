#include "lot/lot_unit.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/dataset.h"
#include "model/greybox_fit.h"
#include "noise/identify.h"

namespace gyrosid {
namespace {

double white_noise_dph_at_1hz(const Dataset& data, const GreyboxEstimate& fit) {
  const Eigen::VectorXd residual_dph = (data.target - fit.model->predict(data)) * units::radps_to_dph(1.0);
  const double dt = median_sample_interval(data.t_s);
  const NoiseIdentification id = identify_noise(std::span<const double>(residual_dph.data(), static_cast<std::size_t>(residual_dph.size())), dt);
  for (const NoiseParameter& p : id.parameters) {
    if (p.name == "N" && p.value > 0.0) return p.value;
  }
  return units::radps_to_dph(fit.residual_sd_radps) * std::sqrt(dt);
}

}  // namespace

LotUnit calibrate_unit(const Recording& recording, const std::string& name, const GreyboxOptions& structure, SolveSummary* summary) {
  const Dataset data = make_dataset(recording, greybox_features(structure), ModelTarget::error);
  GreyboxEstimate fit = estimate_greybox(data, structure, nullptr, summary);
  LotUnit unit{name, std::move(fit.theta), fit.theta_covariance.diagonal(), 0.0};
  unit.white_dph_at_1hz = white_noise_dph_at_1hz(data, fit);
  if (data.size() > 1) unit.recording_min = (data.t_s.back() - data.t_s.front()) / 60.0;
  return unit;
}

LotUnit unit_of_model(const GreyboxModel& model, const std::string& name, const GreyboxOptions& structure) {
  const auto& surface = model.errors().scale_factor_surface;
  std::vector<double> rates_dps;
  if (surface) {
    for (double w : surface->y()) rates_dps.push_back(std::round(units::radps_to_dps(w) * 1e9) / 1e9);
  }
  if (!surface || surface->x() != structure.surface_temperatures_c || rates_dps != structure.surface_rates_dps) {
    auto list = [](const std::vector<double>& v) {
      std::vector<std::string> s;
      for (double x : v) s.push_back(format_number(x));
      return join(s);
    };
    fail(name, ": a lot's units need the scale-factor surface on the lot's grid (temperatures ", list(structure.surface_temperatures_c),
         " C; rates ", list(structure.surface_rates_dps), " dps)");
  }
  return {name, greybox_theta(model.errors(), model.lag_tau_s(), structure), Eigen::VectorXd(), 0.0};
}

}  // namespace gyrosid
