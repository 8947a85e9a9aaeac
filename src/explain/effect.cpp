#include "explain/effect.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/units.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {
namespace {

bool varies(const Eigen::VectorXd& v, double scale) { return v.size() > 1 && (v.maxCoeff() - v.minCoeff()) > scale; }

}  // namespace

std::string_view Candidate::id() const { return effect->id(); }

CandidateContext::CandidateContext(const std::vector<Term>& base_terms, double base_lag, const ExplainInput& input)
    : base(base_terms), base_lag_tau_s(base_lag), in(input) {
  const Signals& s = in.signals;
  duration_s = s.t_s.back() - s.t_s.front();
  temp_varies = varies(s.temp_c, 1.0);
  rate_varies = varies(s.rate, units::dps_to_radps(1.0));
  for (const auto& t : base) {
    if (const auto* p = t.as<TemperaturePolynomial>()) bias_orders.insert(p->orders().begin(), p->orders().end());
    if (const auto* p = t.as<ScaleFactorPolynomial>()) {
      for (const auto& o : p->orders()) sf_orders.insert({o[0], o[1]});
    }
  }
}

std::vector<std::string> CandidateContext::new_varying_channels(const std::vector<std::string>& names, double scale) const {
  std::vector<std::string> out;
  for (const auto& c : names) {
    const bool in_base = std::any_of(base.begin(), base.end(), [&](const Term& t) {
      const auto* ch = t.as<ChannelTerm>();
      if (!ch || ch->squared()) return false;
      const std::vector<std::string> names = ch->channels();
      return std::find(names.begin(), names.end(), c) != names.end();
    });
    if (!in_base && varies(in.signals.channel(c), scale)) out.push_back(c);
  }
  return out;
}

Candidate Effect::candidate(Term term) const {
  Candidate c;
  c.effect = this;
  c.term = std::move(term);
  return c;
}

Eigen::MatrixXd Effect::columns(const Candidate& c, double tau_s, const ModelColumns& m) const {
  const Term t = c.nonlinear == NonlinearParameter::term_parameter ? c.term->with_parameter(tau_s) : *c.term;
  return term_columns(t, m.signals, coil_temperature(m.signals, m.lag_tau_s), m.scaling);
}

std::vector<PhysicalParameter> Effect::parameters(const Term&, const Eigen::VectorXd&, const Eigen::VectorXd&, const TermScaling&) const {
  return {};
}

std::string Effect::separating_experiment(std::string_view) const { return ""; }

std::vector<double> Effect::located_parameters(const ExplainInput&, const Eigen::VectorXd&) const { return {}; }

std::vector<Term> Effect::richer_forms(const Term&, const ExplainInput&) const { return {}; }

const std::vector<const Effect*>& effect_library() {
  static const std::vector<std::unique_ptr<Effect>> owned = [] {
    std::vector<std::unique_ptr<Effect>> v;
    for (const auto& e : effect_registry().entries()) v.push_back(e.make());
    return v;
  }();
  static const std::vector<const Effect*> library = [] {
    std::vector<const Effect*> v;
    for (const auto& e : owned) v.push_back(e.get());
    return v;
  }();
  return library;
}

const Effect& find_effect(std::string_view id) {
  for (const Effect* e : effect_library()) {
    if (e->id() == id) return *e;
  }
  fail("unknown effect '", id, "'; known: ", effect_registry().known());
}

std::string separating_experiment(const Effect& a, const Effect& b) {
  if (std::string s = a.separating_experiment(b.id()); !s.empty()) return s;
  if (std::string s = b.separating_experiment(a.id()); !s.empty()) return s;
  return "vary the two effects' inputs independently so that their regressors stop being proportional";
}

ModelSpec with_effect(const ModelSpec& model, const Candidate& c, double tau) {
  ModelSpec m = model;
  if (c.nonlinear == NonlinearParameter::coil_lag) m.lag_tau_s = tau;
  else m.terms.push_back(c.nonlinear == NonlinearParameter::term_parameter ? c.term->with_parameter(tau) : *c.term);
  return m;
}

Eigen::MatrixXd model_columns(const ModelSpec& m, const Signals& s, const TermScaling& sc) {
  return design_matrix(m.terms, s, coil_temperature(s, m.lag_tau_s), sc);
}

std::vector<double> log_grid(double lo, double hi, int n) {
  std::vector<double> g;
  if (!(hi > lo)) return {lo};
  for (int i = 0; i < n; ++i) g.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)));
  return g;
}

}  // namespace gyrosid::explain
