// Spline terms. The scale-factor error as a bicubic spline surface over a (T, omega) grid (thesis figs
// 3.5/3.6): the not-a-knot interpolation is linear in the grid values, so column (i, j) is omega times the
// surface through a unit value at node (i, j), held at the grid's edge outside it (sensor/spline_surface.h).
// The bias beyond a cubic in the coil temperature: truncated cubics at the knots but the two outermost at each
// end, so that with the cubic they span the not-a-knot cubic splines on the grid (the third derivative
// continuous across the first and last inner knots, as the surface's splines).
#include <algorithm>
#include <cmath>
#include <iomanip>

#include "core/error.h"
#include "core/units.h"
#include "model/spline_surface_c.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {

namespace {

void check_grid(const std::vector<double>& g, const char* kind) {
  const bool finite = std::all_of(g.begin(), g.end(), [](double v) { return std::isfinite(v); });
  if (g.size() < 2 || !finite || !std::is_sorted(g.begin(), g.end()) || std::adjacent_find(g.begin(), g.end()) != g.end()) {
    fail("physics term ", kind, ": grids need at least two strictly increasing values");
  }
}

}  // namespace

ScaleFactorSurface::ScaleFactorSurface(std::vector<double> temps_c, std::vector<double> rates_dps)
    : temps_c_(std::move(temps_c)), rates_dps_(std::move(rates_dps)) {
  for (const auto* g : {&temps_c_, &rates_dps_}) check_grid(*g, "scale_factor_surface");
}

std::vector<std::string> ScaleFactorSurface::column_names() const {
  std::vector<std::string> out;
  for (double t : temps_c_)
    for (double w : rates_dps_) out.push_back(str_cat("w B(", t, " C, ", w, " dps)"));
  return out;
}

namespace {

// The not-a-knot cardinal cubic splines through the knots (unit value at one knot, zero at the others) at
// each x, held at the ends (n x knots): the 1-D factors of the bicubic surface's basis, each evaluated as
// the cubic Hermite interpolant of its knot values and slopes (the surface's own construction).
Eigen::MatrixXd cardinal_splines(const std::vector<double>& knots, const Eigen::VectorXd& x) {
  const Eigen::MatrixXd slope = spline_slope_operator(knots);  // slopes at the knots = slope * values
  const auto m = static_cast<Eigen::Index>(knots.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.size(), m);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double v = std::clamp(x(k), knots.front(), knots.back());
    auto i = static_cast<Eigen::Index>(std::upper_bound(knots.begin(), knots.end(), v) - knots.begin());
    i = std::clamp<Eigen::Index>(i, 1, m - 1) - 1;
    const double h = knots[static_cast<std::size_t>(i) + 1] - knots[static_cast<std::size_t>(i)];
    const double u = (v - knots[static_cast<std::size_t>(i)]) / h, u2 = u * u, u3 = u2 * u;
    out(k, i) += 2 * u3 - 3 * u2 + 1;
    out(k, i + 1) += -2 * u3 + 3 * u2;
    out.row(k) += h * ((u3 - 2 * u2 + u) * slope.row(i) + (u3 - u2) * slope.row(i + 1));
  }
  return out;
}

}  // namespace

// The surface's basis is a tensor product: B_ij(T, w) = a_i(T) b_j(w) with a, b the 1-D cardinal splines.
void ScaleFactorSurface::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::VectorXd& rate = in.signals.rate;
  const Eigen::MatrixXd a = cardinal_splines(temps_c_, in.coil.temp_c);
  const Eigen::MatrixXd b = cardinal_splines(rates_dps_, rate * units::kRadToDeg);
  const auto nw = static_cast<Eigen::Index>(rates_dps_.size());
  for (Eigen::Index i = 0; i < a.cols(); ++i) {
    for (Eigen::Index j = 0; j < nw; ++j) out.col(i * nw + j) = rate.cwiseProduct(a.col(i)).cwiseProduct(b.col(j));
  }
}

void ScaleFactorSurface::parameters_json(nlohmann::json& j) const {
  j["grid"] = {{"temperatures_c", temps_c_}, {"rates_dps", rates_dps_}};
}

std::string ScaleFactorSurface::export_c(TermCode& code) const {
  const auto nt = static_cast<Eigen::Index>(temps_c_.size()), nw = static_cast<Eigen::Index>(rates_dps_.size());
  Eigen::MatrixXd values(nt, nw);
  for (Eigen::Index i = 0; i < nt; ++i)
    for (Eigen::Index j = 0; j < nw; ++j) values(i, j) = code.values(i * nw + j);
  const SplineSurface surface(temps_c_, rates_dps_, values, OutsideGridPolicy::clamp);
  emit_spline_surface_data(code.out, code.stem, surface);
  emit_spline_surface_function(code.out, code.stem, static_cast<int>(nt), static_cast<int>(nw));
  code.body << "  { double d; e += w * " << code.out.id(code.stem) << "surface(" << code.input("temperature") << ", w * " << std::hexfloat
            << units::kRadToDeg << std::defaultfloat << ", &d); }\n";
  return "";
}

Term scale_factor_surface(std::vector<double> temps_c, std::vector<double> rates_dps) {
  return Term(std::make_shared<ScaleFactorSurface>(std::move(temps_c), std::move(rates_dps)));
}

TemperatureSpline::TemperatureSpline(std::vector<double> knots_c) : knots_c_(std::move(knots_c)) {
  check_grid(knots_c_, "bias_temperature_spline");
  if (knots_c_.size() < 5) fail("physics term bias_temperature_spline: needs at least five knots");
}

double TemperatureSpline::spacing_c() const { return (knots_c_.back() - knots_c_.front()) / static_cast<double>(knots_c_.size() - 1); }

std::vector<std::string> TemperatureSpline::column_names() const {
  std::vector<std::string> out;
  for (std::size_t i = 2; i + 2 < knots_c_.size(); ++i) out.push_back(str_cat("((T - ", knots_c_[i], " C)+ / ", spacing_c(), " C)^3"));
  return out;
}

void TemperatureSpline::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::ArrayXd t = in.coil.temp_c.array().max(knots_c_.front()).min(knots_c_.back());
  for (std::size_t i = 2; i + 2 < knots_c_.size(); ++i) {
    out.col(static_cast<Eigen::Index>(i - 2)) = ((t - knots_c_[i]).max(0.0) / spacing_c()).cube().matrix();
  }
}

std::string TemperatureSpline::export_c(TermCode& code) const {
  code.body << std::hexfloat << "  { const double tc = fmin(fmax(" << code.input("temperature") << ", " << knots_c_.front() << "), "
            << knots_c_.back() << ");\n";
  for (std::size_t i = 2; i + 2 < knots_c_.size(); ++i) {
    code.body << "    e += " << code.coefficient(static_cast<int>(i - 2)) << " * pow(fmax(tc - " << knots_c_[i] << ", 0.0) / " << spacing_c() << ", 3);\n";
  }
  code.body << std::defaultfloat << "  }\n";
  return "";
}

Term temperature_spline(std::vector<double> knots_c) { return Term(std::make_shared<TemperatureSpline>(std::move(knots_c))); }

}  // namespace gyrosid
