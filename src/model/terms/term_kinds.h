// The kinds of physics term (physics_terms.h), each one self-describing class. Columns (rad/s per unit
// coefficient unless stated), with dT = (T_coil - t_ref) / t_scale, u = omega / rate_scale, omega the true
// rate:
//
//   bias                  1
//   bias_temperature      dT^k                       for each order k >= 1
//   scale_factor          omega dT^i u^j             for each (i, j)                      (thesis eq 3.48)
//   scale_factor_surface  omega B_ij(T, omega)       the bicubic-spline basis of a (T, omega) grid (fig 3.6)
//   asymmetry             |omega|                    (dSF differs by 2 beta between the senses)
//   shupe                 dT_coil/dt, deg C/s        (eq 3.3)
//   hysteresis            +1/2 heating, -1/2 cooling, held through plateaus
//   warmup                exp(-(t - t0) / tau)       t0 the first sample
//   aging                 (t - t0) / 3600 s
//   channel               named recorded channels as they are (specific force, magnetic field, other axes)
//   channel_squared       their squares
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "model/physics_terms.h"

namespace gyrosid {

class BiasTerm : public TermBasis {
 public:
  std::string_view kind() const override { return "bias"; }
  int size() const override { return 1; }
  std::vector<std::string> column_names() const override { return {"bias"}; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::string export_c(TermCode& code) const override;
};

class TemperaturePolynomial : public TermBasis {
 public:
  explicit TemperaturePolynomial(std::vector<int> orders);
  std::string_view kind() const override { return "bias_temperature"; }
  int size() const override { return static_cast<int>(orders_.size()); }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["orders"] = orders_; }
  bool uses_temperature() const override { return true; }
  std::shared_ptr<const TermBasis> subset(const std::vector<int>& columns) const override;
  std::string export_c(TermCode& code) const override;
  const std::vector<int>& orders() const { return orders_; }

 private:
  std::vector<int> orders_;
};

class ScaleFactorPolynomial : public TermBasis {
 public:
  using Orders = std::vector<std::array<int, 2>>;  // (i, j): powers of dT and u
  explicit ScaleFactorPolynomial(Orders orders);
  std::string_view kind() const override { return "scale_factor"; }
  int size() const override { return static_cast<int>(orders_.size()); }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["sf_orders"] = orders_; }
  bool uses_temperature() const override { return true; }
  std::shared_ptr<const TermBasis> subset(const std::vector<int>& columns) const override;
  std::string export_c(TermCode& code) const override;
  const Orders& orders() const { return orders_; }

 private:
  Orders orders_;
};

class ScaleFactorSurface : public TermBasis {
 public:
  ScaleFactorSurface(std::vector<double> temps_c, std::vector<double> rates_dps);
  std::string_view kind() const override { return "scale_factor_surface"; }
  int size() const override { return static_cast<int>(temps_c_.size() * rates_dps_.size()); }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override;
  bool uses_temperature() const override { return true; }
  std::string export_c(TermCode& code) const override;
  const std::vector<double>& temps_c() const { return temps_c_; }
  const std::vector<double>& rates_dps() const { return rates_dps_; }

 private:
  std::vector<double> temps_c_, rates_dps_;
};

class AsymmetryTerm : public TermBasis {
 public:
  std::string_view kind() const override { return "asymmetry"; }
  int size() const override { return 1; }
  std::vector<std::string> column_names() const override { return {"asymmetry"}; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::string export_c(TermCode& code) const override;
};

// Terms with memory: zero in steady state, not exportable as a stateless function.
class HistoryTerm : public TermBasis {
 public:
  int size() const override { return 1; }
  std::vector<std::string> column_names() const override { return {std::string(kind())}; }
  std::string export_c(TermCode& code) const override;
};

class ShupeTerm : public HistoryTerm {
 public:
  std::string_view kind() const override { return "shupe"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  TermMemory memory() const override { return TermMemory::temperature_history; }
  bool uses_temperature() const override { return true; }
};

class HysteresisTerm : public HistoryTerm {
 public:
  std::string_view kind() const override { return "hysteresis"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  TermMemory memory() const override { return TermMemory::temperature_history; }
};

class WarmupTerm : public HistoryTerm {
 public:
  explicit WarmupTerm(double tau_s);
  std::string_view kind() const override { return "warmup"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["tau_s"] = tau_s_; }
  TermMemory memory() const override { return TermMemory::time; }
  std::optional<double> time_constant_s() const override { return tau_s_; }
  std::shared_ptr<const TermBasis> with_time_constant(double tau_s) const override;

 private:
  double tau_s_;
};

class AgingTerm : public HistoryTerm {
 public:
  std::string_view kind() const override { return "aging"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  TermMemory memory() const override { return TermMemory::time; }
};

class ChannelTerm : public TermBasis {
 public:
  ChannelTerm(std::vector<std::string> channels, bool squared);
  std::string_view kind() const override { return squared_ ? "channel_squared" : "channel"; }
  int size() const override { return static_cast<int>(channels_.size()); }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["channels"] = channels_; }
  std::vector<std::string> channels() const override { return channels_; }
  std::string export_c(TermCode& code) const override;
  bool squared() const { return squared_; }

 private:
  std::vector<std::string> channels_;
  bool squared_;
};

// Value constructors.
Term bias_term();
Term temperature_polynomial(std::vector<int> orders);
Term scale_factor_polynomial(ScaleFactorPolynomial::Orders orders);
Term scale_factor_surface(std::vector<double> temps_c, std::vector<double> rates_dps);
Term asymmetry_term();
Term shupe_term();
Term hysteresis_term();
Term warmup_term(double tau_s);
Term aging_term();
Term channel_term(std::vector<std::string> channels, bool squared = false);

}  // namespace gyrosid
