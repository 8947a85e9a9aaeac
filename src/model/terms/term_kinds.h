// The kinds of physics term (physics_terms.h), each one self-describing class. Columns (rad/s per unit
// coefficient unless stated), with dT = (T_coil - t_ref) / t_scale, u = omega / rate_scale, omega the true
// rate:
//
//   bias                  1
//   bias_temperature      dT^k                       for each order k >= 1
//   scale_factor          omega dT^i u^j             for each (i, j)                      (thesis eq 3.48)
//   scale_factor_surface  omega B_ij(T, omega)       the bicubic-spline basis of a (T, omega) grid (fig 3.6)
//   bias_temperature_spline  ((T - k_i)+ / h)^3      for the knots k_2 .. k_{n-3} of a grid k_0 .. k_{n-1} of coil
//                                                    temperatures (spacing h, T held to the grid): beside a
//                                                    cubic bias, the not-a-knot cubic splines on the grid - a
//                                                    bias of any smooth shape in T (a bump, a knee) with
//                                                    coefficients the base cannot take
//   asymmetry             |omega|                    (dSF differs by 2 beta between the senses)
//   shupe                 dT_coil/dt, deg C/s        (eq 3.3); with gradient_tau_s, d/dt of T_coil through a
//                         first-order lag of that time constant (the gradient's diffusion)
//   hysteresis            (T - P_r(T)) / 2r: the play operator of half-width r = width/2 (Preisach's elementary
//                         hysteron): +1/2 once heating has moved T by `width`, -1/2 once cooling has, linear
//                         in between, held through plateaus (width 0: the legacy switch at a rate threshold);
//                         with second_width_c, a second column, the play of that width (a two-width loop)
//   warmup                exp(-(t - t0) / tau)       t0 the first sample
//   aging                 (t - t0) / 3600 s
//   aging_log             (tau / 3600 s) ln(1 + (t - t0) / tau): ageing that slows (slope 1/h at t0)
//   channel               named recorded channels as they are (specific force, magnetic field, other axes)
//   channel_squared       their squares
//   bias_step             1 from time t_s on, else 0             (a change point: outside the physics library);
//                         with recovery_tau_s, a second column exp(-(t - t_s) / tau) from t_s on (a step that
//                         partly recovers: a hop whose disturbance then relaxes)
//   bias_ramp             (t - t_s) / 3600 s from t_s on, else 0 (a trend starting at t_s: likewise); with
//                         curved, a second column, its square (a trend that accelerates or slows)
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

class TemperatureSpline : public TermBasis {
 public:
  explicit TemperatureSpline(std::vector<double> knots_c);
  std::string_view kind() const override { return "bias_temperature_spline"; }
  int size() const override { return static_cast<int>(knots_c_.size()) - 4; }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["knots_c"] = knots_c_; }
  double spacing_c() const;  // the mean knot spacing h
  bool uses_temperature() const override { return true; }
  std::string export_c(TermCode& code) const override;
  const std::vector<double>& knots_c() const { return knots_c_; }

 private:
  std::vector<double> knots_c_;
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

// The Shupe bias follows the coil's radial thermal gradient (thesis eq 3.3). Its rate form (gradient_tau_s
// = 0) is dT_coil/dt; with gradient_tau_s > 0 the gradient relaxes by diffusion with that time constant:
// (T_coil - L) / tau = dL/dt, L the coil temperature through a first-order lag of tau - the rate of
// temperature for changes slower than tau, less for faster ones. Both in deg C/s.
class ShupeTerm : public HistoryTerm {
 public:
  explicit ShupeTerm(double gradient_tau_s = 0.0);
  std::string_view kind() const override { return "shupe"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override;
  TermMemory memory() const override { return TermMemory::temperature_history; }
  bool uses_temperature() const override { return true; }
  double gradient_tau_s() const { return gradient_tau_s_; }

 private:
  double gradient_tau_s_;
};

// One play of width_c, or two (a Prandtl-Ishlinskii loop of two widths, one column each) when second_width_c
// > 0: the loop's height is the sum of the two coefficients. The nonlinear parameter is width_c (the second
// width is chosen on a grid where the loop is extended: explain's richer forms).
class HysteresisTerm : public HistoryTerm {
 public:
  explicit HysteresisTerm(double width_c = 0.0, double second_width_c = 0.0);  // width 0: the legacy threshold switch
  std::string_view kind() const override { return "hysteresis"; }
  int size() const override { return second_width_c_ > 0 ? 2 : 1; }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override;
  TermMemory memory() const override { return TermMemory::temperature_history; }
  std::optional<TermParameter> parameter() const override;
  std::shared_ptr<const TermBasis> with_parameter(double width_c) const override;
  double second_width_c() const { return second_width_c_; }

 private:
  double width_c_, second_width_c_;
};

class WarmupTerm : public HistoryTerm {
 public:
  explicit WarmupTerm(double tau_s);
  std::string_view kind() const override { return "warmup"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override { j["tau_s"] = tau_s_; }
  TermMemory memory() const override { return TermMemory::time; }
  std::optional<TermParameter> parameter() const override { return TermParameter{"tau_s", tau_s_, true}; }
  std::shared_ptr<const TermBasis> with_parameter(double tau_s) const override;

 private:
  double tau_s_;
};

// A change of the bias at time t_s: a step (ramp = false) or the start of a trend (ramp = true). A step with
// recovery_tau_s > 0 has a second column, exp(-(t - t_s) / recovery_tau_s) from t_s on: the step's height is
// the sum of the two coefficients, what lasts the first. A curved trend has a second column ((t - t_s) / 1 h)^2
// (a drift that accelerates or slows). The nonlinear parameter is t_s (the recovery's time constant is chosen
// on a grid where the step is extended, the curve's onset likewise: explain's richer forms).
class ChangeTerm : public HistoryTerm {
 public:
  ChangeTerm(double t_s, bool ramp, double recovery_tau_s = 0.0, bool curved = false);
  std::string_view kind() const override { return ramp_ ? "bias_ramp" : "bias_step"; }
  int size() const override { return recovery_tau_s_ > 0 || curved_ ? 2 : 1; }
  std::vector<std::string> column_names() const override;
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override;
  TermMemory memory() const override { return TermMemory::time; }
  std::optional<TermParameter> parameter() const override { return TermParameter{"t_s", t_s_, false}; }
  std::shared_ptr<const TermBasis> with_parameter(double t_s) const override {
    return std::make_shared<ChangeTerm>(t_s, ramp_, recovery_tau_s_, curved_);
  }
  double recovery_tau_s() const { return recovery_tau_s_; }

 private:
  double t_s_;
  bool ramp_;
  double recovery_tau_s_;
  bool curved_;
};

// Ageing of the bias from the first sample t0: linear, (t - t0) / 1 h (tau_s = 0, kind aging), or slowing
// logarithmically, (tau / 1 h) ln(1 + (t - t0) / tau) (tau_s > 0, kind aging_log; its slope at t0 is the
// coefficient per hour, and it tends to the linear one as tau grows).
class AgingTerm : public HistoryTerm {
 public:
  explicit AgingTerm(double tau_s = 0.0);
  std::string_view kind() const override { return tau_s_ > 0 ? "aging_log" : "aging"; }
  void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void parameters_json(nlohmann::json& j) const override;
  TermMemory memory() const override { return TermMemory::time; }
  std::optional<TermParameter> parameter() const override;
  std::shared_ptr<const TermBasis> with_parameter(double tau_s) const override { return std::make_shared<AgingTerm>(tau_s); }

 private:
  double tau_s_;
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
Term temperature_spline(std::vector<double> knots_c);
Term asymmetry_term();
Term shupe_term(double gradient_tau_s = 0.0);
Term hysteresis_term(double width_c = 0.0, double second_width_c = 0.0);
Term change_term(double t_s, bool ramp);
Term recovering_step_term(double t_s, double recovery_tau_s);
Term curved_ramp_term(double t_s);
Term warmup_term(double tau_s);
Term aging_term(double tau_s = 0.0);
Term channel_term(std::vector<std::string> channels, bool squared = false);

}  // namespace gyrosid
