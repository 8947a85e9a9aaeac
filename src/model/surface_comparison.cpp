#include "model/surface_comparison.h"

#include <cmath>

#include "core/earth.h"
#include "core/error.h"
#include "core/units.h"

namespace gyrosid {

std::string SurfaceGridSpec::validate() const {
  if (!(temp_max_c > temp_min_c)) return "temperature range is empty";
  if (!(rate_max_dps > rate_min_dps)) return "rate range is empty";
  if (temp_points < 2 || rate_points < 2) return "a grid needs at least 2 x 2 points";
  return "";
}

namespace {
std::vector<double> even_points(double low, double high, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(low + (high - low) * i / (n - 1));
  return v;
}
}  // namespace

std::vector<double> SurfaceGridSpec::temperatures_c() const { return even_points(temp_min_c, temp_max_c, temp_points); }
std::vector<double> SurfaceGridSpec::rates_dps() const { return even_points(rate_min_dps, rate_max_dps, rate_points); }

nlohmann::json SurfaceStats::to_json() const {
  return {{"mean_dph", mean_dph}, {"sigma_dph", sigma_dph}, {"max_dph", max_dph}, {"min_dph", min_dph}, {"rms_dph", rms_dph}};
}

nlohmann::json SigmaStats::to_json() const {
  return {{"rms_sigma_dph", rms_sigma_dph}, {"max_sigma_dph", max_sigma_dph}, {"coverage_95", coverage_95}};
}

SurfaceStats surface_stats(const Eigen::MatrixXd& diff) {
  SurfaceStats s;
  const double n = static_cast<double>(diff.size());
  s.mean_dph = diff.mean();
  s.sigma_dph = std::sqrt((diff.array() - s.mean_dph).square().sum() / std::max(1.0, n - 1));
  s.max_dph = diff.maxCoeff();
  s.min_dph = diff.minCoeff();
  s.rms_dph = std::sqrt(diff.squaredNorm() / n);
  return s;
}

namespace {

// A model's inputs in steady state at measured rate wm and temperature T: temperature rate 0, specific force
// 1 g along the input axis.
void steady_inputs(const CalibrationModel& model, double wm, double temp_c, double* x) {
  const double gravity = earth::normal_gravity(0.0);
  for (std::size_t k = 0; k < model.features().size(); ++k) {
    const std::string& f = model.features()[k];
    if (f == "measured_rate") x[k] = wm;
    else if (f == "temperature") x[k] = temp_c;
    else if (f == "temperature_rate") x[k] = 0.0;
    else if (f == "accel_x_mps2" || f == "accel_y_mps2") x[k] = 0.0;
    else if (f == "accel_z_mps2") x[k] = gravity;
    else fail("surface comparison: no steady-state value for model input '", f, "'");
  }
}

}  // namespace

SurfaceComparison compare_surfaces(const CalibrationModel& model, const GyroSensor& truth, const SurfaceGridSpec& g) {
  if (auto p = g.validate(); !p.empty()) fail("surface grid: ", p);
  SurfaceComparison c;
  c.temps_c = g.temperatures_c();
  c.rates_dps = g.rates_dps();
  c.true_dph.resize(g.temp_points, g.rate_points);
  c.estimated_dph.resize(g.temp_points, g.rate_points);
  const double gravity = earth::normal_gravity(0.0);
  std::vector<double> x(model.features().size());
  Eigen::MatrixXd inputs(g.temp_points * g.rate_points, static_cast<Eigen::Index>(x.size()));  // row i * rates + j
  for (int i = 0; i < g.temp_points; ++i) {
    for (int j = 0; j < g.rate_points; ++j) {
      GyroEnvironment env;
      env.temp_c = c.temps_c[static_cast<std::size_t>(i)];
      env.f_s = Eigen::Vector3d(0, 0, gravity);
      const double w = units::dps_to_radps(c.rates_dps[static_cast<std::size_t>(j)]);
      const double wm = truth.errors.forward(w, env);
      steady_inputs(model, wm, env.temp_c, x.data());
      for (std::size_t k = 0; k < x.size(); ++k) inputs(i * g.rate_points + j, static_cast<Eigen::Index>(k)) = x[k];
      const double p = model.predict(x.data());
      const double estimated_error = model.target() == ModelTarget::error ? p : wm - p;
      c.true_dph(i, j) = units::radps_to_dph(wm - w);
      c.estimated_dph(i, j) = units::radps_to_dph(estimated_error);
    }
  }
  c.stats = surface_stats(c.difference_dph());
  if (model.posterior()) {
    const Eigen::VectorXd sigma = model.predict_with_sigma(inputs).sigma;
    c.sigma_dph.resize(g.temp_points, g.rate_points);
    int inside = 0;
    for (int i = 0; i < g.temp_points; ++i)
      for (int j = 0; j < g.rate_points; ++j) {
        c.sigma_dph(i, j) = units::radps_to_dph(sigma(i * g.rate_points + j));
        inside += std::abs(c.estimated_dph(i, j) - c.true_dph(i, j)) <= 1.96 * c.sigma_dph(i, j);
      }
    c.sigma_stats.rms_sigma_dph = std::sqrt(c.sigma_dph.squaredNorm() / static_cast<double>(c.sigma_dph.size()));
    c.sigma_stats.max_sigma_dph = c.sigma_dph.maxCoeff();
    c.sigma_stats.coverage_95 = static_cast<double>(inside) / static_cast<double>(c.sigma_dph.size());
  }
  return c;
}

SigmaMap predictive_sigma_map(const CalibrationModel& model, std::vector<double> temps_c, std::vector<double> rates_dps) {
  SigmaMap m;
  m.temps_c = std::move(temps_c), m.rates_dps = std::move(rates_dps);
  const auto nt = static_cast<Eigen::Index>(m.temps_c.size()), nw = static_cast<Eigen::Index>(m.rates_dps.size());
  if (nt == 0 || nw == 0) fail("predictive sigma map: the grid is empty");
  Eigen::MatrixXd inputs(nt * nw, static_cast<Eigen::Index>(model.features().size()));  // row i * nw + j
  std::vector<double> x(model.features().size());
  for (Eigen::Index i = 0; i < nt; ++i) {
    for (Eigen::Index j = 0; j < nw; ++j) {
      steady_inputs(model, units::dps_to_radps(m.rates_dps[static_cast<std::size_t>(j)]), m.temps_c[static_cast<std::size_t>(i)], x.data());
      for (std::size_t k = 0; k < x.size(); ++k) inputs(i * nw + j, static_cast<Eigen::Index>(k)) = x[k];
    }
  }
  const Eigen::VectorXd sigma = model.predict_with_sigma(inputs).sigma;
  m.sigma_dph = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(sigma.data(), nt, nw).unaryExpr([](double v) { return units::radps_to_dph(v); });
  Eigen::Index at_t = 0, at_w = 0;
  m.max_dph = m.sigma_dph.maxCoeff(&at_t, &at_w);
  m.max_temp_c = m.temps_c[static_cast<std::size_t>(at_t)], m.max_rate_dps = m.rates_dps[static_cast<std::size_t>(at_w)];
  m.rms_dph = std::sqrt(m.sigma_dph.squaredNorm() / static_cast<double>(m.sigma_dph.size()));
  return m;
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

}  // namespace gyrosid
