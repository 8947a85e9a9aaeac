// Terms with memory - the time since the first sample or the temperature history: Shupe (thesis eq 3.3,
// bias proportional to the coil temperature's rate), heating/cooling hysteresis, warm-up transient, ageing.
#include <cmath>

#include "core/error.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {
namespace {

double first_time(const TermInputs& in) { return in.signals.t_s.empty() ? 0.0 : in.signals.t_s.front(); }

}  // namespace

std::string HistoryTerm::export_c(TermCode&) const {
  return str_cat("the term '", kind(), "' needs time or the temperature history; not exportable as a stateless function");
}

void ShupeTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const { out.col(0) = in.coil.rate_c_per_s; }

void HysteresisTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  out.col(0) = thermal_branch(in.signals, in.coil, in.scaling);
}

WarmupTerm::WarmupTerm(double tau_s) : tau_s_(tau_s) {
  if (!(tau_s_ > 0)) fail("physics term warmup: tau_s must be positive");
}

void WarmupTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const double t0 = first_time(in);
  for (Eigen::Index i = 0; i < out.rows(); ++i) out(i, 0) = std::exp(-(in.signals.t_s[static_cast<std::size_t>(i)] - t0) / tau_s_);
}

std::shared_ptr<const TermBasis> WarmupTerm::with_time_constant(double tau_s) const { return std::make_shared<WarmupTerm>(tau_s); }

void AgingTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  const double t0 = first_time(in);
  for (Eigen::Index i = 0; i < out.rows(); ++i) out(i, 0) = (in.signals.t_s[static_cast<std::size_t>(i)] - t0) / 3600.0;
}

Term shupe_term() { return Term(std::make_shared<ShupeTerm>()); }
Term hysteresis_term() { return Term(std::make_shared<HysteresisTerm>()); }
Term warmup_term(double tau_s) { return Term(std::make_shared<WarmupTerm>(tau_s)); }
Term aging_term() { return Term(std::make_shared<AgingTerm>()); }

}  // namespace gyrosid
