#include "model/physics_terms.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/thermal_lag.h"
#include "core/units.h"
#include "model/dataset.h"

namespace gyrosid {

const Eigen::VectorXd& Signals::channel(const std::string& name) const {
  const auto it = channels.find(name);
  if (it == channels.end()) {
    std::string known;
    for (const auto& [k, v] : channels) known += (known.empty() ? "" : ", ") + k;
    fail("physics term needs the channel '", name, "', which the data lack (channels: ", known.empty() ? "none" : known, ")");
  }
  return it->second;
}

nlohmann::json TermScaling::to_json() const {
  return {{"t_ref_c", t_ref_c}, {"t_scale_c", t_scale_c}, {"rate_scale_radps", rate_scale_radps},
          {"hysteresis_threshold_c_per_s", hysteresis_threshold_c_per_s}};
}

TermScaling TermScaling::from_json(const nlohmann::json& j) {
  TermScaling s;
  s.t_ref_c = j.at("t_ref_c").get<double>();
  s.t_scale_c = j.at("t_scale_c").get<double>();
  s.rate_scale_radps = j.at("rate_scale_radps").get<double>();
  s.hysteresis_threshold_c_per_s = j.at("hysteresis_threshold_c_per_s").get<double>();
  if (!(s.t_scale_c > 0) || !(s.rate_scale_radps > 0) || !(s.hysteresis_threshold_c_per_s > 0)) {
    fail("physics terms: scales must be positive");
  }
  return s;
}

TermScaling TermScaling::of(const Signals& s) {
  TermScaling out;
  if (s.size() == 0) return out;
  const double lo = s.temp_c.minCoeff(), hi = s.temp_c.maxCoeff();
  out.t_ref_c = 0.5 * (lo + hi);
  out.t_scale_c = std::max(1.0, 0.5 * (hi - lo));  // a probe's quantisation is no temperature range
  const double peak = s.rate.cwiseAbs().maxCoeff();
  out.rate_scale_radps = peak > units::dps_to_radps(1.0) ? peak : 1.0;
  return out;
}

namespace {

// The probe's rate by local linear regression over +-30 s: a probe read to a few hundredths of a degree
// makes the sample-to-sample difference noise (0.01 C over 1 s is 0.6 C/min), and noise in a regressor
// biases its coefficient and hands the fit to any smoother column (a short "lag"). Symmetric: no delay.
//
// The window's sums are kept as it slides (O(n), not O(n x window): at 100 Hz a window holds 6000 samples), in
// offsets from an anchor sample that moves with the window - re-anchored, and the sums recomputed, each time
// the window has moved on by its own length - so that the centred sums lose no more than two digits.
class SlidingRegression {
 public:
  SlidingRegression(const std::vector<double>& t, const std::vector<double>& v) : t_(t), v_(v) {}
  void anchor(std::size_t lo, std::size_t hi) {
    t0_ = t_[lo], v0_ = v_[lo], st_ = sv_ = stt_ = stv_ = 0.0, anchor_ = lo;
    for (std::size_t k = lo; k <= hi; ++k) add(k, 1.0);
  }
  void add(std::size_t k, double sign) {
    const double dt = t_[k] - t0_, dv = v_[k] - v0_;
    st_ += sign * dt, sv_ += sign * dv, stt_ += sign * dt * dt, stv_ += sign * dt * dv;
  }
  std::size_t anchored_at() const { return anchor_; }
  // The slope over the window's m samples.
  double slope(double m) const {
    const double ctt = stt_ - st_ * st_ / m, ctv = stv_ - st_ * sv_ / m;
    return ctt > 0 ? ctv / ctt : 0.0;
  }

 private:
  const std::vector<double>& t_;
  const std::vector<double>& v_;
  double t0_ = 0.0, v0_ = 0.0, st_ = 0.0, sv_ = 0.0, stt_ = 0.0, stv_ = 0.0;
  std::size_t anchor_ = 0;
};

std::vector<double> probe_rate(const std::vector<double>& t, const std::vector<double>& v) {
  constexpr double kHalfWindowS = 30.0;
  const std::size_t n = v.size();
  std::vector<double> d(n, 0.0);
  if (n == 0) return d;
  SlidingRegression window(t, v);
  std::size_t lo = 0, hi = 0;
  window.anchor(0, 0);
  for (std::size_t i = 0; i < n; ++i) {
    while (hi + 1 < n && t[hi + 1] <= t[i] + kHalfWindowS) window.add(++hi, 1.0);
    while (t[lo] < t[i] - kHalfWindowS) window.add(lo++, -1.0);
    if (lo - window.anchored_at() > std::max<std::size_t>(hi - lo + 1, 64)) window.anchor(lo, hi);
    // At least one neighbour on each side where there is one.
    const bool before = lo == i && i > 0, after = hi == i && i + 1 < n;
    if (before) window.add(i - 1, 1.0);
    if (after) window.add(i + 1, 1.0);
    d[i] = window.slope(static_cast<double>(hi - lo + 1 + before + after));
    if (before) window.add(i - 1, -1.0);
    if (after) window.add(i + 1, -1.0);
  }
  return d;
}

}  // namespace

CoilTemperature coil_temperature(const Signals& s, double tau) {
  CoilTemperature c;
  std::vector<double> probe(s.temp_c.data(), s.temp_c.data() + s.size());
  if (tau > 0) {
    const ThermalLagResponse r = thermal_lag_response({0.0, {tau}}, PiecewiseLinear{s.t_s, probe}, s.t_s);
    c.temp_c = Eigen::Map<const Eigen::VectorXd>(r.stage[0].data(), s.size());
    c.rate_c_per_s = Eigen::Map<const Eigen::VectorXd>(r.output_rate.data(), s.size());
  } else {
    c.temp_c = s.temp_c;
    const std::vector<double> rate = probe_rate(s.t_s, probe);
    c.rate_c_per_s = Eigen::Map<const Eigen::VectorXd>(rate.data(), s.size());
  }
  return c;
}

Eigen::VectorXd thermal_branch(const Signals& s, const CoilTemperature& coil, const TermScaling& scaling) {
  const Eigen::Index n = s.size();
  Eigen::VectorXd branch = Eigen::VectorXd::Zero(n);
  if (n == 0) return branch;
  // The temperature change over a +-30 s window (a probe's quantisation and noise make the sample-to-sample
  // rate useless), compared with the threshold rate times the window.
  std::size_t lo = 0, hi = 0;
  double state = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = s.t_s[static_cast<std::size_t>(i)];
    while (s.t_s[lo] < t - 30.0) ++lo;
    while (hi + 1 < static_cast<std::size_t>(n) && s.t_s[hi + 1] <= t + 30.0) ++hi;
    const double span = s.t_s[hi] - s.t_s[lo];
    if (span > 0) {
      const double rate = (coil.temp_c(static_cast<Eigen::Index>(hi)) - coil.temp_c(static_cast<Eigen::Index>(lo))) / span;
      if (rate > scaling.hysteresis_threshold_c_per_s) state = 0.5;
      else if (rate < -scaling.hysteresis_threshold_c_per_s) state = -0.5;
    }
    branch(i) = state;
  }
  // Before the first ramp the branch is unknown: take the first one seen.
  Eigen::Index first = 0;
  while (first < n && branch(first) == 0.0) ++first;
  if (first < n) branch.head(first).setConstant(branch(first));
  return branch;
}

std::shared_ptr<const TermBasis> TermBasis::subset(const std::vector<int>&) const { return shared_from_this(); }

std::shared_ptr<const TermBasis> TermBasis::with_parameter(double) const { fail("physics term ", kind(), " has no nonlinear parameter"); }

Term::Term(std::shared_ptr<const TermBasis> basis) : basis_(std::move(basis)) {
  if (!basis_) fail("physics term: empty");
  if (basis_->size() == 0) fail("physics term ", basis_->kind(), " has no columns");
}

std::optional<Term> Term::subset(const std::vector<int>& columns) const {
  auto s = basis_->subset(columns);
  if (!s) return std::nullopt;
  return Term(std::move(s));
}

nlohmann::json Term::to_json() const {
  nlohmann::json j = {{"kind", std::string(kind())}};
  basis_->parameters_json(j);
  return j;
}

Term Term::from_json(const nlohmann::json& j) {
  const std::string kind = j.at("kind").get<std::string>();
  return Term(std::shared_ptr<const TermBasis>(term_kinds().make(kind, j)));
}

Eigen::MatrixXd term_columns(const Term& term, const Signals& s, const CoilTemperature& coil, const TermScaling& sc) {
  Eigen::MatrixXd x(s.size(), term.size());
  term->columns({s, coil, sc}, x);
  return x;
}

int total_columns(const std::vector<Term>& terms) {
  int cols = 0;
  for (const auto& t : terms) cols += t.size();
  return cols;
}

Eigen::MatrixXd design_matrix(const std::vector<Term>& terms, const Signals& s, const CoilTemperature& coil, const TermScaling& sc) {
  Eigen::MatrixXd x(s.size(), total_columns(terms));
  const TermInputs in{s, coil, sc};
  int at = 0;
  for (const auto& t : terms) {
    t->columns(in, x.middleCols(at, t.size()));
    at += t.size();
  }
  return x;
}

}  // namespace gyrosid
