#include "model/greybox_model.h"

#include <Eigen/QR>
#include <nlopt.hpp>

#include <chrono>
#include <cmath>
#include <iomanip>

#include "core/error.h"
#include "core/thermal_lag.h"
#include "core/units.h"

namespace gyrosid {

std::string GreyboxOptions::validate() const {
  if (bias_order < 0 || bias_order > 8) return str_cat("bias_order = ", bias_order, " must be in [0, 8]");
  if (sf_temperature_order < 0 || sf_temperature_order > 6) return "sf_temperature_order must be in [0, 6]";
  if (sf_rate_order < 0 || sf_rate_order > 10) return "sf_rate_order must be in [0, 10]";
  if (scale_factor == ScaleFactorForm::surface && (surface_temperatures_c.size() < 2 || surface_rates_dps.size() < 2)) {
    return "surface grids need at least two temperatures and two rates";
  }
  if (!(lag_max_s > 1.0)) return "lag_max_s must exceed 1 s";
  if (!(ridge >= 0 && ridge < 1)) return "ridge must be in [0, 1)";
  return "";
}

std::vector<std::string> greybox_features(const GreyboxOptions& o) {
  std::vector<std::string> f{"measured_rate", "temperature"};
  if (o.g_sensitivity) {
    for (const char* a : {"accel_x_mps2", "accel_y_mps2", "accel_z_mps2"}) f.emplace_back(a);
  }
  return f;
}

GreyboxModel::GreyboxModel(std::vector<std::string> features, GyroErrorModel errors, double lag_tau_s)
    : CalibrationModel(std::move(features), ModelTarget::error), errors_(std::move(errors)), lag_tau_s_(lag_tau_s) {
  for (std::size_t i = 0; i < features_.size(); ++i) {
    if (features_[i] == "accel_x_mps2") accel_index_ = static_cast<int>(i);
    if (features_[i] == "temperature_rate") temp_rate_index_ = static_cast<int>(i);
  }
  if (features_.size() < 2 || features_[0] != "measured_rate" || features_[1] != "temperature") {
    fail("greybox model: the first features must be measured_rate, temperature");
  }
}

GyroEnvironment GreyboxModel::environment(const double* x, double coil_temp_c, double coil_rate) const {
  GyroEnvironment env;
  env.temp_c = coil_temp_c;
  env.temp_rate_c_per_s = coil_rate;
  if (accel_index_ >= 0) env.f_s = Eigen::Vector3d(x[accel_index_], x[accel_index_ + 1], x[accel_index_ + 2]);
  return env;
}

double GreyboxModel::predict(const double* x) const {
  const double rate = temp_rate_index_ >= 0 ? x[temp_rate_index_] : 0.0;
  return x[0] - errors_.inverse(x[0], environment(x, x[1], rate));
}

namespace {

struct CoilTemperature {
  std::vector<double> temp, rate;
};

// The coil temperature along a recording: the probe through a first-order lag (exact for the linearly
// interpolated probe), or the probe itself with its central-difference rate.
CoilTemperature coil_temperature(const std::vector<double>& t, const std::vector<double>& probe, double tau) {
  if (tau <= 0) return {probe, time_derivative(t, probe)};
  PiecewiseLinear input{t, probe};
  const ThermalLagResponse r = thermal_lag_response({0.0, {tau}}, input, t);
  return {r.stage[0], r.output_rate};
}

std::vector<double> column(const Dataset& d, Eigen::Index k) { return {d.x.col(k).data(), d.x.col(k).data() + d.size()}; }

}  // namespace

Eigen::VectorXd GreyboxModel::predict(const Dataset& data) const {
  const CoilTemperature coil = coil_temperature(data.t_s, column(data, 1), lag_tau_s_);
  Eigen::VectorXd out(data.size());
  std::vector<double> row(static_cast<std::size_t>(data.x.cols()));
  for (Eigen::Index i = 0; i < data.size(); ++i) {
    for (Eigen::Index k = 0; k < data.x.cols(); ++k) row[static_cast<std::size_t>(k)] = data.x(i, k);
    const std::size_t s = static_cast<std::size_t>(i);
    out(i) = row[0] - errors_.inverse(row[0], environment(row.data(), coil.temp[s], coil.rate[s]));
  }
  return out;
}

namespace {

nlohmann::json polynomial_json(const Polynomial& p) { return {{"reference", p.reference}, {"coefficients", p.coefficients}}; }
Polynomial polynomial_of(const nlohmann::json& j) {
  return {j.at("coefficients").get<std::vector<double>>(), j.at("reference").get<double>()};
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
  if (e.scale_factor_surface) {
    const SplineSurface& s = *e.scale_factor_surface;
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index i = 0; i < s.values().rows(); ++i) {
      std::vector<double> row;
      for (Eigen::Index k = 0; k < s.values().cols(); ++k) row.push_back(s.values()(i, k));
      rows.push_back(row);
    }
    j["scale_factor_surface"] = {{"temperatures_c", s.x()}, {"rates_radps", s.y()}, {"values", rows},
                                 {"outside", to_string(s.outside())}};
  }
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
  if (j.contains("scale_factor_surface")) {
    const auto& s = j.at("scale_factor_surface");
    const auto rows = s.at("values").get<std::vector<std::vector<double>>>();
    const auto x = s.at("temperatures_c").get<std::vector<double>>(), y = s.at("rates_radps").get<std::vector<double>>();
    Eigen::MatrixXd v(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(y.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i].size() != y.size()) fail("greybox model: surface row ", i, " has ", rows[i].size(), " values");
      for (std::size_t k = 0; k < y.size(); ++k) v(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k];
    }
    e.scale_factor_surface = SplineSurface(x, y, v, parse_enum<OutsideGridPolicy>(s.at("outside").get<std::string>()));
  }
  return std::make_unique<GreyboxModel>(std::move(features), std::move(e), j.value("lag_tau_s", 0.0));
}

nlohmann::json GreyboxFitSummary::to_json() const {
  return {{"termination", "solved"}, {"samples", samples},       {"parameters", parameters},
          {"rms_residual_dph", rms_residual_dph}, {"lag_tau_s", lag_tau_s}, {"lag_evaluations", lag_evaluations},
          {"time_s", time_s}};
}

namespace {

// The linear part of the fit for a given coil temperature: columns of the forward regression.
struct GreyboxDesign {
  const Dataset& data;
  const GreyboxOptions& o;
  double t0 = 25.0, ts = 1.0, ws = 1.0;
  std::vector<SplineSurface> unit_surfaces;  // one per grid node
  Eigen::Index p = 0;

  GreyboxDesign(const Dataset& d, const GreyboxOptions& options) : data(d), o(options) {
    const auto temp = d.x.col(1);
    t0 = 0.5 * (temp.maxCoeff() + temp.minCoeff());
    ts = std::max(0.5 * (temp.maxCoeff() - temp.minCoeff()), 1.0);
    ws = std::max(d.reference.cwiseAbs().maxCoeff(), 1e-6);
    if (o.scale_factor == ScaleFactorForm::surface) {
      std::vector<double> rates;
      for (double r : o.surface_rates_dps) rates.push_back(units::dps_to_radps(r));
      const Eigen::Index nt = static_cast<Eigen::Index>(o.surface_temperatures_c.size()), nw = static_cast<Eigen::Index>(rates.size());
      for (Eigen::Index a = 0; a < nt; ++a)
        for (Eigen::Index b = 0; b < nw; ++b) {
          Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(nt, nw);
          unit(a, b) = 1.0;
          unit_surfaces.emplace_back(o.surface_temperatures_c, rates, unit, OutsideGridPolicy::clamp);
        }
    }
    p = (o.bias_order + 1) + (o.scale_factor == ScaleFactorForm::surface ? static_cast<Eigen::Index>(unit_surfaces.size())
                                                                         : o.sf_temperature_order + o.sf_rate_order + 1) +
        (o.shupe ? 1 : 0) + (o.asymmetry ? 1 : 0) + (o.g_sensitivity ? 3 : 0);
  }

  Eigen::MatrixXd matrix(const CoilTemperature& coil) const {
    const Eigen::Index n = data.size();
    Eigen::MatrixXd a(n, p);
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const double w = data.reference(i), v = (coil.temp[s] - t0) / ts, u = w / ws;
      Eigen::Index c = 0;
      double vp = 1.0;
      for (int k = 0; k <= o.bias_order; ++k, vp *= v) a(i, c++) = vp;
      if (o.scale_factor == ScaleFactorForm::surface) {
        for (const auto& unit : unit_surfaces) a(i, c++) = unit(coil.temp[s], w).value * w;
      } else {
        vp = v;
        for (int k = 1; k <= o.sf_temperature_order; ++k, vp *= v) a(i, c++) = vp * w;
        double up = 1.0;
        for (int k = 0; k <= o.sf_rate_order; ++k, up *= u) a(i, c++) = up * w;
      }
      if (o.shupe) a(i, c++) = coil.rate[s];
      if (o.asymmetry) a(i, c++) = 0.5 * std::abs(w);
      if (o.g_sensitivity) {
        for (int k = 0; k < 3; ++k) a(i, c++) = data.x(i, 2 + k);
      }
    }
    return a;
  }

  // Ridge-regularised least squares by pivoted QR on unit-norm columns; returns coefficients and RSS.
  Eigen::VectorXd solve(const Eigen::MatrixXd& a, double* rss) const {
    const Eigen::Index n = a.rows();
    const Eigen::VectorXd norm = a.colwise().norm().transpose().cwiseMax(1e-300);
    Eigen::MatrixXd aug(n + p, p);
    aug.topRows(n) = a * norm.cwiseInverse().asDiagonal();
    aug.bottomRows(p) = std::sqrt(o.ridge) * Eigen::MatrixXd::Identity(p, p);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + p);
    rhs.head(n) = data.target;
    const Eigen::VectorXd coeff = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(aug).solve(rhs).cwiseQuotient(norm);
    if (rss) *rss = (a * coeff - data.target).squaredNorm();
    return coeff;
  }

  GyroErrorModel to_error_model(const Eigen::VectorXd& c) const {
    GyroErrorModel e;
    Eigen::Index k = 0;
    e.bias_temperature_radps.reference = t0;
    for (int i = 0; i <= o.bias_order; ++i) e.bias_temperature_radps.coefficients.push_back(c(k++) / std::pow(ts, i));
    if (o.scale_factor == ScaleFactorForm::surface) {
      const Eigen::Index nt = static_cast<Eigen::Index>(o.surface_temperatures_c.size());
      const Eigen::Index nw = static_cast<Eigen::Index>(o.surface_rates_dps.size());
      Eigen::MatrixXd v(nt, nw);
      for (Eigen::Index a = 0; a < nt; ++a)
        for (Eigen::Index b = 0; b < nw; ++b) v(a, b) = c(k++);
      e.scale_factor_surface = SplineSurface(unit_surfaces.front().x(), unit_surfaces.front().y(), v, OutsideGridPolicy::clamp);
    } else {
      e.scale_factor_temperature.reference = t0;
      e.scale_factor_temperature.coefficients.push_back(0.0);
      for (int i = 1; i <= o.sf_temperature_order; ++i) e.scale_factor_temperature.coefficients.push_back(c(k++) / std::pow(ts, i));
      for (int i = 0; i <= o.sf_rate_order; ++i) e.scale_factor_rate.coefficients.push_back(c(k++) / std::pow(ws, i));
    }
    if (o.shupe) e.shupe_rad_per_c = c(k++);
    if (o.asymmetry) e.scale_factor_asymmetry = c(k++);
    if (o.g_sensitivity) {
      for (int i = 0; i < 3; ++i) e.g_sensitivity(i) = c(k++);
    }
    return e;
  }
};

}  // namespace

std::unique_ptr<GreyboxModel> fit_greybox(const Dataset& data, const GreyboxOptions& o, GreyboxFitSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  if (auto p = o.validate(); !p.empty()) fail("greybox model: ", p);
  if (data.features != greybox_features(o)) {
    std::string want;
    for (const auto& f : greybox_features(o)) want += (want.empty() ? "" : ", ") + f;
    fail("greybox model: features must be ", want);
  }
  if (!data.target.allFinite()) fail("greybox model: the recording has no reference rate (ref_rate_dps) to fit against");
  const GreyboxDesign design(data, o);
  if (data.size() < 2 * design.p) fail("greybox model: ", data.size(), " samples for ", design.p, " coefficients");
  const std::vector<double> probe = column(data, 1);

  auto rss_at = [&](double tau) {
    double rss = 0.0;
    design.solve(design.matrix(coil_temperature(data.t_s, probe, tau)), &rss);
    return rss;
  };
  double tau = 0.0;
  int evaluations = 0;
  if (o.thermal_lag) {
    // Coarse log grid (the RSS in tau can have several dips), then BOBYQA on log tau from the best point;
    // tau = 0 (no lag) stays a candidate.
    double best_rss = rss_at(0.0), best_log = -INFINITY;
    ++evaluations;
    const double lo = 0.0, hi = std::log(o.lag_max_s);
    for (int i = 0; i <= 12; ++i) {
      const double lt = lo + (hi - lo) * i / 12.0;
      const double r = rss_at(std::exp(lt));
      ++evaluations;
      if (r < best_rss) best_rss = r, best_log = lt;
    }
    if (std::isfinite(best_log)) {
      nlopt::opt opt(nlopt::LN_BOBYQA, 1);
      opt.set_lower_bounds(std::vector<double>{lo});
      opt.set_upper_bounds(std::vector<double>{hi});
      opt.set_xtol_abs(1e-4);
      opt.set_maxeval(60);
      auto objective = [](const std::vector<double>& x, std::vector<double>&, void* self) {
        auto* f = static_cast<std::function<double(double)>*>(self);
        return (*f)(x[0]);
      };
      std::function<double(double)> f = [&](double lt) {
        ++evaluations;
        return rss_at(std::exp(lt));
      };
      opt.set_min_objective(objective, &f);
      std::vector<double> x{best_log};
      double value = best_rss;
      try {
        opt.optimize(x, value);
      } catch (const std::exception&) {
        // BOBYQA may stop on roundoff; x holds its best point.
      }
      tau = value <= best_rss ? std::exp(x[0]) : std::exp(best_log);
    }
  }
  const CoilTemperature coil = coil_temperature(data.t_s, probe, tau);
  const Eigen::MatrixXd a = design.matrix(coil);
  double rss = 0.0;
  const Eigen::VectorXd c = design.solve(a, &rss);
  auto model = std::make_unique<GreyboxModel>(data.features, design.to_error_model(c), tau);
  if (summary) {
    summary->samples = static_cast<std::size_t>(data.size());
    summary->parameters = static_cast<std::size_t>(design.p) + (o.thermal_lag ? 1 : 0);
    summary->rms_residual_dph = units::radps_to_dph(std::sqrt(rss / static_cast<double>(data.size())));
    summary->lag_tau_s = tau;
    summary->lag_evaluations = evaluations;
    summary->time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return model;
}

// --- C export -------------------------------------------------------------------------------------------

void GreyboxModel::export_c_body(CExport& out) const {
  const GyroErrorModel& e = errors_;
  const std::string p = out.prefix;
  auto poly = [&](const std::string& name, const Polynomial& q) {
    out.array(name, q.coefficients.data(), q.coefficients.size());
    out.source << "static const double " << p << "_" << name << "_ref = " << std::hexfloat << q.reference
               << std::defaultfloat << ";\n";
  };
  poly("bias_t", e.bias_temperature_radps);
  poly("sf_t", e.scale_factor_temperature);
  poly("sf_w", e.scale_factor_rate);
  const bool surface = e.scale_factor_surface.has_value();
  int nx = 0, ny = 0;
  if (surface) {
    const SplineSurface& s = *e.scale_factor_surface;
    nx = static_cast<int>(s.x().size());
    ny = static_cast<int>(s.y().size());
    out.array("sx", s.x().data(), s.x().size());
    out.array("sy", s.y().data(), s.y().size());
    auto grid = [&](const std::string& name, const Eigen::MatrixXd& m) {
      std::vector<double> v;  // row-major: [i * ny + j]
      for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) v.push_back(m(i, j));
      out.array(name, v.data(), v.size());
    };
    grid("sf", s.values());
    grid("sfx", s.d_dx());
    grid("sfy", s.d_dy());
    grid("sfxy", s.d2_dxdy());
  }
  out.source << std::hexfloat;
  out.source << "\nstatic double " << p << "_poly(const double* c, int n, double ref, double x, double* slope) {\n"
             << "  double v = 0.0, d = 0.0, u = x - ref;\n  int i;\n"
             << "  for (i = n - 1; i >= 0; --i) v = v * u + c[i];\n"
             << "  for (i = n - 1; i >= 1; --i) d = d * u + (double)i * c[i];\n"
             << "  if (slope) *slope = d;\n  return v;\n}\n";
  if (surface) {
    out.source << "\nstatic int " << p << "_locate(const double* k, int n, double v) {\n"
               << "  int i = 0;\n  while (i < n - 2 && v >= k[i + 1]) ++i;\n  return i;\n}\n"
               << "\n/* Bicubic Hermite patch of the spline surface; held at the edge outside the grid. */\n"
               << "static double " << p << "_surface(double x, double y, double* d_dy) {\n"
               << "  const int xo = x < " << p << "_sx[0] || x > " << p << "_sx[" << nx - 1 << "];\n"
               << "  const int yo = y < " << p << "_sy[0] || y > " << p << "_sy[" << ny - 1 << "];\n"
               << "  int i, j, a, b;\n  double hx, hy, u, v, bu[4], bv[4], dv[4], val = 0.0, dy = 0.0;\n"
               << "  if (x < " << p << "_sx[0]) x = " << p << "_sx[0];\n"
               << "  if (x > " << p << "_sx[" << nx - 1 << "]) x = " << p << "_sx[" << nx - 1 << "];\n"
               << "  if (y < " << p << "_sy[0]) y = " << p << "_sy[0];\n"
               << "  if (y > " << p << "_sy[" << ny - 1 << "]) y = " << p << "_sy[" << ny - 1 << "];\n"
               << "  i = " << p << "_locate(" << p << "_sx, " << nx << ", x);\n"
               << "  j = " << p << "_locate(" << p << "_sy, " << ny << ", y);\n"
               << "  hx = " << p << "_sx[i + 1] - " << p << "_sx[i];\n  hy = " << p << "_sy[j + 1] - " << p << "_sy[j];\n"
               << "  u = (x - " << p << "_sx[i]) / hx;\n  v = (y - " << p << "_sy[j]) / hy;\n"
               << "  { const double u2 = u * u, u3 = u2 * u, v2 = v * v, v3 = v2 * v;\n"
               << "    bu[0] = 2 * u3 - 3 * u2 + 1; bu[1] = -2 * u3 + 3 * u2; bu[2] = u3 - 2 * u2 + u; bu[3] = u3 - u2;\n"
               << "    bv[0] = 2 * v3 - 3 * v2 + 1; bv[1] = -2 * v3 + 3 * v2; bv[2] = v3 - 2 * v2 + v; bv[3] = v3 - v2;\n"
               << "    dv[0] = 6 * v2 - 6 * v; dv[1] = -6 * v2 + 6 * v; dv[2] = 3 * v2 - 4 * v + 1; dv[3] = 3 * v2 - 2 * v; }\n"
               << "  for (a = 0; a < 4; ++a) {\n    for (b = 0; b < 4; ++b) {\n"
               << "      const int ii = i + (a & 1), jj = j + (b & 1), at = ii * " << ny << " + jj;\n"
               << "      const double sx = a >= 2 ? hx : 1.0, sy = b >= 2 ? hy : 1.0;\n"
               << "      double c;\n"
               << "      if (a < 2 && b < 2) c = " << p << "_sf[at];\n"
               << "      else if (a >= 2 && b < 2) c = sx * " << p << "_sfx[at];\n"
               << "      else if (a < 2) c = sy * " << p << "_sfy[at];\n"
               << "      else c = sx * sy * " << p << "_sfxy[at];\n"
               << "      val += bu[a] * bv[b] * c;\n"
               << "      dy += bu[a] * dv[b] * c / hy;\n    }\n  }\n"
               << "  (void)xo;\n  *d_dy = yo ? 0.0 : dy;\n  return val;\n}\n";
  }
  out.source << "\n/* Scale-factor error dSF(T, w) and its slope in w (GyroErrorModel::scale_factor_error). */\n"
             << "static double " << p << "_sf_error(double t, double w, double* slope) {\n"
             << "  double st, sw, value;\n"
             << "  value = " << p << "_poly(" << p << "_sf_t, " << e.scale_factor_temperature.coefficients.size() << ", "
             << p << "_sf_t_ref, t, &st) + " << p << "_poly(" << p << "_sf_w, " << e.scale_factor_rate.coefficients.size()
             << ", " << p << "_sf_w_ref, w, &sw);\n"
             << "  *slope = sw;\n";
  if (surface) out.source << "  { double ds; value += " << p << "_surface(t, w, &ds); *slope += ds; }\n";
  out.source << "  if (w > 0) value += 0.5 * " << e.scale_factor_asymmetry << ";\n"
             << "  if (w < 0) value -= 0.5 * " << e.scale_factor_asymmetry << ";\n"
             << "  return value;\n}\n"
             << "\n/* Steady-state compensation: solves w (1 + dSF(T, w)) + d = w_meas (GyroErrorModel::inverse). */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  const double t = x[1];\n"
             << "  double d = " << e.bias_radps << " + " << p << "_poly(" << p << "_bias_t, "
             << e.bias_temperature_radps.coefficients.size() << ", " << p << "_bias_t_ref, t, 0);\n";
  if (accel_index_ >= 0) {
    out.source << "  d += " << e.g_sensitivity.x() << " * x[" << accel_index_ << "] + " << e.g_sensitivity.y() << " * x["
               << accel_index_ + 1 << "] + " << e.g_sensitivity.z() << " * x[" << accel_index_ + 2 << "];\n";
  }
  out.source << "  {\n    const double target = x[0] - d;\n"
             << "    double w = target, step = 1e-6 * (1.0 + fabs(target)), lo = w, hi = w, slope, f, next;\n    int iter;\n"
             << "#define PHI(W) ((W) * (1.0 + " << p << "_sf_error(t, (W), &slope)) - target)\n"
             << "    while (PHI(lo) > 0) lo -= (step *= 2.0);\n"
             << "    step = 1e-6 * (1.0 + fabs(target));\n"
             << "    while (PHI(hi) < 0) hi += (step *= 2.0);\n"
             << "    w = 0.5 * (lo + hi);\n"
             << "    for (iter = 0; iter < 200; ++iter) {\n"
             << "      const double sf = " << p << "_sf_error(t, w, &slope);\n"
             << "      f = w * (1.0 + sf) - target;\n"
             << "      slope = 1.0 + sf + w * slope;\n"
             << "      if (f == 0.0) break;\n"
             << "      if (f < 0) lo = w; else hi = w;\n"
             << "      next = slope > 0 ? w - f / slope : 0.5 * (lo + hi);\n"
             << "      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);\n"
             << "      if (fabs(next - w) <= 4e-16 * fmax(1.0, fabs(w)) || hi - lo <= 4e-16 * fmax(1.0, fabs(w))) { w = next; break; }\n"
             << "      w = next;\n    }\n#undef PHI\n"
             << "    return x[0] - w;\n  }\n}\n";
  out.source << std::defaultfloat;
}

}  // namespace gyrosid
