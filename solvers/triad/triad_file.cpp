#include "solvers/triad/triad_file.h"

#include <cmath>

#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {
namespace {

nlohmann::json matrix(const Eigen::Matrix3d& m, const std::array<std::array<bool, 3>, 3>& known, double scale = 1.0) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < 3; ++j) row.push_back(known[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] ? number_or_null(m(i, j) * scale) : nlohmann::json(nullptr));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json observable_json(const TriadFit& f) {
  nlohmann::json entries = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (f.uncertainty.misalignment_known[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]) entries.push_back(std::string("M_") + kTriadAxes[i] + kTriadAxes[j]);
    }
  }
  nlohmann::json combinations = nlohmann::json::array();
  for (const auto& c : f.angles.combinations) {
    combinations.push_back({{"entry", c.entry}, {"angles", c.expression}, {"observable", c.observable}});
  }
  nlohmann::json angles = nlohmann::json::object();
  for (std::size_t k = 0; k < f.angles.angles.size(); ++k) angles[f.angles.angles[k]] = static_cast<bool>(f.angles.angle_observable[k]);
  return {{"entries", entries},
          {"angle_combinations", combinations},
          {"independent_combinations", f.angles.rank},
          {"physical_angles", angles},
          {"explanation", "To first order the measurement matrix depends on the twelve angles of the IA->RA->CA->B chain only "
                          "through the six sums of eq 3.72 (IA->RA angle + insertion angle per gyro and axis); no angle is "
                          "observable alone, a sum exactly when its matrix entry is. The diagonal holds scale-factor errors, "
                          "not angles."},
          {"notes", f.notes}};
}

}  // namespace

nlohmann::json triad_fit_json(const TriadFit& f, const nlohmann::json& training) {
  const TriadUncertainty& u = f.uncertainty;
  nlohmann::json j = triad_model_json(f.model, &u.misalignment_known);
  j["misalignment"]["sigma"] = matrix(u.misalignment_sigma, u.misalignment_known);
  j["misalignment"]["inflation"] = matrix(u.misalignment_inflation, u.misalignment_known);
  j["misalignment"]["units"] = "row i = gyro i (x, y, z), column j = body axis; diagonal: scale-factor error (dimensionless), off-diagonal: rad";
  nlohmann::json value = nlohmann::json::array(), sigma = nlohmann::json::array(), coeff_sigma = nlohmann::json::array();
  for (std::size_t a = 0; a < 3; ++a) {
    const bool known = !u.bias_known[a].empty() && u.bias_known[a][0];
    value.push_back(known ? number_or_null(units::radps_to_dph(f.model.bias.coefficients[a](0))) : nlohmann::json(nullptr));
    sigma.push_back(known ? number_or_null(units::radps_to_dph(u.bias_sigma[a](0))) : nlohmann::json(nullptr));
    nlohmann::json cs = nlohmann::json::array();
    for (Eigen::Index k = 0; k < u.bias_sigma[a].size(); ++k) {
      cs.push_back(u.bias_known[a][static_cast<std::size_t>(k)] ? number_or_null(units::radps_to_dph(u.bias_sigma[a](k))) : nlohmann::json(nullptr));
    }
    coeff_sigma.push_back(cs);
  }
  j["bias_dph"] = {{"value", value}, {"sigma", sigma}, {"temperature_c", f.model.bias.reference_c}};
  j["bias"]["sigma_dph"] = coeff_sigma;
  if (f.model.g_sensitivity) {
    j["g_sensitivity_dph_per_mps2"] = matrix(*f.model.g_sensitivity, u.g_sensitivity_known, units::radps_to_dph(1.0));
    j["g_sensitivity_sigma_dph_per_mps2"] = matrix(*u.g_sensitivity_sigma, u.g_sensitivity_known, units::radps_to_dph(1.0));
  }
  j["observable"] = observable_json(f);
  nlohmann::json noise = nlohmann::json::array(), rms = nlohmann::json::array();
  for (std::size_t a = 0; a < 3; ++a) {
    noise.push_back(number_or_null(units::radps_to_dph(u.noise_radps[a])));
    rms.push_back(f.residual_rms_dph[a]);
  }
  j["noise_dph"] = noise;
  j["noise_density_radps_rt_hz"] = {number_or_null(f.noise_density[0]), number_or_null(f.noise_density[1]), number_or_null(f.noise_density[2])};
  j["sample_rate_hz"] = f.sample_rate_hz;
  j["residual_rms_dph"] = rms;
  j["reference"] = f.reference;
  j["summary"] = f.summary;
  j["training"] = training;
  return j;
}

}  // namespace gyrosid
