// The scale-factor error as a bicubic spline surface over a (T, omega) grid (thesis figs 3.5/3.6): the
// not-a-knot interpolation is linear in the grid values, so column (i, j) is omega times the surface
// through a unit value at node (i, j), held at the grid's edge outside it.
#include <algorithm>
#include <iomanip>

#include "core/error.h"
#include "core/units.h"
#include "model/spline_surface_c.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {

ScaleFactorSurface::ScaleFactorSurface(std::vector<double> temps_c, std::vector<double> rates_dps)
    : temps_c_(std::move(temps_c)), rates_dps_(std::move(rates_dps)) {
  for (const auto* g : {&temps_c_, &rates_dps_}) {
    if (g->size() < 2 || !std::is_sorted(g->begin(), g->end()) || std::adjacent_find(g->begin(), g->end()) != g->end()) {
      fail("physics term scale_factor_surface: grids need at least two strictly increasing values");
    }
  }
}

std::vector<std::string> ScaleFactorSurface::column_names() const {
  std::vector<std::string> out;
  for (double t : temps_c_)
    for (double w : rates_dps_) out.push_back(str_cat("w B(", t, " C, ", w, " dps)"));
  return out;
}

void ScaleFactorSurface::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const std::size_t nt = temps_c_.size(), nw = rates_dps_.size();
  const Eigen::VectorXd& rate = in.signals.rate;
  for (std::size_t i = 0; i < nt; ++i) {
    for (std::size_t j = 0; j < nw; ++j) {
      Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nt), static_cast<Eigen::Index>(nw));
      unit(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = 1.0;
      const SplineSurface basis(temps_c_, rates_dps_, unit, OutsideGridPolicy::clamp);
      const auto col = static_cast<Eigen::Index>(i * nw + j);
      for (Eigen::Index k = 0; k < rate.size(); ++k) out(k, col) = rate(k) * basis(in.coil.temp_c(k), units::radps_to_dps(rate(k))).value;
    }
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

}  // namespace gyrosid
