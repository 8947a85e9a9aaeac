// Terms with memory - the time since the first sample or the temperature history: Shupe (thesis eq 3.3,
// bias proportional to the coil temperature's rate), heating/cooling hysteresis, warm-up transient, ageing,
// and changes of the bias at a time (a step, a trend starting) that no physics of the library explains.
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/thermal_lag.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {
namespace {

double first_time(const TermInputs& in) { return in.signals.t_s.empty() ? 0.0 : in.signals.t_s.front(); }

}  // namespace

std::string HistoryTerm::export_c(TermCode&) const {
  return str_cat("the term '", kind(), "' needs time or the temperature history; not exportable as a stateless function");
}

ShupeTerm::ShupeTerm(double gradient_tau_s) : gradient_tau_s_(gradient_tau_s) {
  if (!(gradient_tau_s_ >= 0)) fail("physics term shupe: gradient_tau_s must be >= 0");
}

void ShupeTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  if (gradient_tau_s_ == 0.0) {
    out.col(0) = in.coil.rate_c_per_s;
    return;
  }
  const Eigen::VectorXd& coil = in.coil.temp_c;
  const ThermalLagResponse r = thermal_lag_response({0.0, {gradient_tau_s_}}, PiecewiseLinear{in.signals.t_s, {coil.data(), coil.data() + coil.size()}},
                                                    in.signals.t_s);
  out.col(0) = Eigen::Map<const Eigen::VectorXd>(r.output_rate.data(), out.rows());
}

void ShupeTerm::parameters_json(nlohmann::json& j) const {
  if (gradient_tau_s_ > 0) j["gradient_tau_s"] = gradient_tau_s_;
}

HysteresisTerm::HysteresisTerm(double width_c, double second_width_c) : width_c_(width_c), second_width_c_(second_width_c) {
  if (!(width_c_ >= 0)) fail("physics term hysteresis: width_c must be >= 0");
  if (!(second_width_c_ >= 0)) fail("physics term hysteresis: second_width_c must be >= 0");
  if (second_width_c_ > 0 && !(width_c_ > 0)) fail("physics term hysteresis: second_width_c needs width_c > 0 (two plays, not the threshold switch)");
}

std::vector<std::string> HysteresisTerm::column_names() const {
  if (second_width_c_ > 0) return {"hysteresis", "hysteresis_2"};
  return {"hysteresis"};
}

namespace {

// The play operator P_r (a backlash of half-width r = width/2) on x, as (x - P_r(x)) / width in [-1/2, 1/2],
// started in its neutral state y = x(0) (output 0, midway between the branches): the recording does not say
// which branch the sensor was on at switch-on, and the neutral state assumes neither (Krasnosel'skii-
// Pokrovskii's usual initial state).
void play_column(const Eigen::VectorXd& x, double width, Eigen::Ref<Eigen::VectorXd> out) {
  const double r = 0.5 * width;
  double y = x.size() ? x(0) : 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    y = std::clamp(y, x(i) - r, x(i) + r);
    out(i) = (x(i) - y) / width;
  }
}

}  // namespace

void HysteresisTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  if (width_c_ == 0.0) {
    out.col(0) = thermal_branch(in.signals, in.coil, in.scaling);
    return;
  }
  play_column(in.coil.temp_c, width_c_, out.col(0));
  if (second_width_c_ > 0) play_column(in.coil.temp_c, second_width_c_, out.col(1));
}

void HysteresisTerm::parameters_json(nlohmann::json& j) const {
  if (width_c_ > 0) j["width_c"] = width_c_;
  if (second_width_c_ > 0) j["second_width_c"] = second_width_c_;
}

std::optional<TermParameter> HysteresisTerm::parameter() const {
  if (width_c_ == 0.0) return std::nullopt;
  return TermParameter{"width_c", width_c_, true};
}

std::shared_ptr<const TermBasis> HysteresisTerm::with_parameter(double width_c) const {
  return std::make_shared<HysteresisTerm>(width_c, second_width_c_);
}

WarmupTerm::WarmupTerm(double tau_s) : tau_s_(tau_s) {
  if (!(tau_s_ > 0)) fail("physics term warmup: tau_s must be positive");
}

void WarmupTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const double t0 = first_time(in);
  for (Eigen::Index i = 0; i < out.rows(); ++i) out(i, 0) = std::exp(-(in.signals.t_s[static_cast<std::size_t>(i)] - t0) / tau_s_);
}

std::shared_ptr<const TermBasis> WarmupTerm::with_parameter(double tau_s) const { return std::make_shared<WarmupTerm>(tau_s); }

ChangeTerm::ChangeTerm(double t_s, bool ramp, double recovery_tau_s, bool curved)
    : t_s_(t_s), ramp_(ramp), recovery_tau_s_(recovery_tau_s), curved_(curved) {
  if (!std::isfinite(t_s_)) fail(str_cat("physics term ", kind(), ": t_s must be finite"));
  if (!(recovery_tau_s_ >= 0)) fail(str_cat("physics term ", kind(), ": recovery_tau_s must be >= 0"));
  if (ramp_ && recovery_tau_s_ > 0) fail("physics term bias_ramp: recovery_tau_s belongs to a step (bias_step), not a trend");
  if (!ramp_ && curved_) fail("physics term bias_step: curved belongs to a trend (bias_ramp), not a step");
}

std::vector<std::string> ChangeTerm::column_names() const {
  if (recovery_tau_s_ > 0) return {"bias_step", "bias_step_recovery"};
  if (curved_) return {"bias_ramp", "bias_ramp_squared"};
  return {std::string(kind())};
}

void ChangeTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  for (Eigen::Index i = 0; i < out.rows(); ++i) {
    const double dt = in.signals.t_s[static_cast<std::size_t>(i)] - t_s_;
    out(i, 0) = dt < 0 ? 0.0 : ramp_ ? dt / 3600.0 : 1.0;
    if (recovery_tau_s_ > 0) out(i, 1) = dt < 0 ? 0.0 : std::exp(-dt / recovery_tau_s_);
    if (curved_) out(i, 1) = out(i, 0) * out(i, 0);
  }
}

void ChangeTerm::parameters_json(nlohmann::json& j) const {
  j["t_s"] = t_s_;
  if (recovery_tau_s_ > 0) j["recovery_tau_s"] = recovery_tau_s_;
  if (curved_) j["curved"] = true;
}

AgingTerm::AgingTerm(double tau_s) : tau_s_(tau_s) {
  if (!(tau_s_ >= 0)) fail("physics term aging_log: tau_s must be positive (0: linear ageing, the term aging)");
}

void AgingTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const double t0 = first_time(in);
  for (Eigen::Index i = 0; i < out.rows(); ++i) {
    const double dt = in.signals.t_s[static_cast<std::size_t>(i)] - t0;
    out(i, 0) = tau_s_ > 0 ? tau_s_ / 3600.0 * std::log1p(dt / tau_s_) : dt / 3600.0;
  }
}

void AgingTerm::parameters_json(nlohmann::json& j) const {
  if (tau_s_ > 0) j["tau_s"] = tau_s_;
}

std::optional<TermParameter> AgingTerm::parameter() const {
  if (tau_s_ == 0.0) return std::nullopt;
  return TermParameter{"tau_s", tau_s_, true};
}

Term shupe_term(double gradient_tau_s) { return Term(std::make_shared<ShupeTerm>(gradient_tau_s)); }
Term hysteresis_term(double width_c, double second_width_c) { return Term(std::make_shared<HysteresisTerm>(width_c, second_width_c)); }
Term change_term(double t_s, bool ramp) { return Term(std::make_shared<ChangeTerm>(t_s, ramp)); }
Term recovering_step_term(double t_s, double recovery_tau_s) { return Term(std::make_shared<ChangeTerm>(t_s, false, recovery_tau_s)); }
Term curved_ramp_term(double t_s) { return Term(std::make_shared<ChangeTerm>(t_s, true, 0.0, true)); }
Term warmup_term(double tau_s) { return Term(std::make_shared<WarmupTerm>(tau_s)); }
Term aging_term(double tau_s) { return Term(std::make_shared<AgingTerm>(tau_s)); }

}  // namespace gyrosid
