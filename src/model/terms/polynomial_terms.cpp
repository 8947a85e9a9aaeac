// Terms that are functions of the current temperature and rate: the thesis's unified model (eq 3.48) -
// bias, bias polynomial in T, scale factor polynomial in (T, omega) - and the scale-factor asymmetry.
#include <algorithm>

#include "core/error.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {
namespace {

Eigen::ArrayXd scaled_temperature(const TermInputs& in) {
  return (in.coil.temp_c.array() - in.scaling.t_ref_c) / in.scaling.t_scale_c;
}

template <typename T>
std::vector<T> pick(const std::vector<T>& all, const std::vector<int>& columns) {
  std::vector<T> out;
  for (int c : columns) out.push_back(all.at(static_cast<std::size_t>(c)));
  return out;
}

}  // namespace

void BiasTerm::columns(const TermInputs&, Eigen::Ref<Eigen::MatrixXd> out) const { out.setOnes(); }

std::string BiasTerm::export_c(TermCode& code) const {
  code.body << "  e += " << code.coefficient(0) << ";\n";
  return "";
}

TemperaturePolynomial::TemperaturePolynomial(std::vector<int> orders) : orders_(std::move(orders)) {
  for (int k : orders_) {
    if (k < 1 || k > 8) fail("physics term bias_temperature: order ", k, " outside [1, 8]");
  }
}

std::vector<std::string> TemperaturePolynomial::column_names() const {
  std::vector<std::string> out;
  for (int k : orders_) out.push_back(str_cat("dT^", k));
  return out;
}

void TemperaturePolynomial::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::ArrayXd dt = scaled_temperature(in);
  for (std::size_t c = 0; c < orders_.size(); ++c) out.col(static_cast<Eigen::Index>(c)) = dt.pow(orders_[c]).matrix();
}

std::shared_ptr<const TermBasis> TemperaturePolynomial::subset(const std::vector<int>& columns) const {
  if (columns.empty()) return nullptr;
  return std::make_shared<TemperaturePolynomial>(pick(orders_, columns));
}

std::string TemperaturePolynomial::export_c(TermCode& code) const {
  for (std::size_t c = 0; c < orders_.size(); ++c) {
    code.body << "  e += " << code.coefficient(static_cast<int>(c)) << " * pow(dT, " << orders_[c] << ");\n";
  }
  return "";
}

ScaleFactorPolynomial::ScaleFactorPolynomial(Orders orders) : orders_(std::move(orders)) {
  for (const auto& p : orders_) {
    if (p[0] < 0 || p[0] > 6 || p[1] < 0 || p[1] > 8) fail("physics term scale_factor: orders (", p[0], ", ", p[1], ") out of range");
  }
}

std::vector<std::string> ScaleFactorPolynomial::column_names() const {
  std::vector<std::string> out;
  for (const auto& p : orders_) out.push_back(str_cat("w dT^", p[0], " u^", p[1]));
  return out;
}

void ScaleFactorPolynomial::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::ArrayXd dt = scaled_temperature(in);
  const Eigen::ArrayXd u = in.signals.rate.array() / in.scaling.rate_scale_radps;
  for (std::size_t c = 0; c < orders_.size(); ++c) {
    const auto [i, j] = orders_[c];
    out.col(static_cast<Eigen::Index>(c)) = (in.signals.rate.array() * dt.pow(i) * u.pow(j)).matrix();
  }
}

std::shared_ptr<const TermBasis> ScaleFactorPolynomial::subset(const std::vector<int>& columns) const {
  if (columns.empty()) return nullptr;
  return std::make_shared<ScaleFactorPolynomial>(pick(orders_, columns));
}

std::string ScaleFactorPolynomial::export_c(TermCode& code) const {
  for (std::size_t c = 0; c < orders_.size(); ++c) {
    code.body << "  e += " << code.coefficient(static_cast<int>(c)) << " * w * pow(dT, " << orders_[c][0] << ") * pow(u, "
              << orders_[c][1] << ");\n";
  }
  return "";
}

void AsymmetryTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const { out.col(0) = in.signals.rate.cwiseAbs(); }

std::string AsymmetryTerm::export_c(TermCode& code) const {
  code.body << "  e += " << code.coefficient(0) << " * fabs(w);\n";
  return "";
}

Term bias_term() { return Term(std::make_shared<BiasTerm>()); }
Term temperature_polynomial(std::vector<int> orders) { return Term(std::make_shared<TemperaturePolynomial>(std::move(orders))); }
Term scale_factor_polynomial(ScaleFactorPolynomial::Orders orders) {
  return Term(std::make_shared<ScaleFactorPolynomial>(std::move(orders)));
}
Term asymmetry_term() { return Term(std::make_shared<AsymmetryTerm>()); }

}  // namespace gyrosid
