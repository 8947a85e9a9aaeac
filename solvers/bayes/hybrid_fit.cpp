#include "solvers/bayes/hybrid_fit.h"

#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "core/units.h"
#include "model/dataset.h"
#include "model/fit_notes.h"
#include "model/held_inputs.h"
#include "model/terms/term_kinds.h"
#include "solvers/common/candidates.h"

namespace gyrosid {

OptionTable HybridOptions::table() {
  OptionTable t("hybrid");
  t.integer("bias_order", &bias_order, 0, 8, "physics: bias polynomial order in temperature")
      .integer("sf_temperature_order", &sf_temperature_order, 0, 6, "physics: scale factor omega dT^i u^j up to this i")
      .integer("sf_rate_order", &sf_rate_order, 0, 8, "physics: ... and up to this j (u = omega / peak rate)")
      .flag("asymmetry", &asymmetry, "physics: scale-factor asymmetry |omega|")
      .text("surface_temperatures_c", &surface_temperatures_c, "physics: scale factor as a bicubic surface on these temperatures (with surface_rates_dps) instead of the polynomial")
      .text("surface_rates_dps", &surface_rates_dps, "physics: the surface's rates, deg/s");
  bind(t);
  return t;
}

std::string HybridOptions::validate() const {
  if (surface_temperatures_c.empty() != surface_rates_dps.empty()) return "give both surface_temperatures_c and surface_rates_dps, or neither";
  for (const auto& [text, key] : {std::pair{surface_temperatures_c, "surface_temperatures_c"}, {surface_rates_dps, "surface_rates_dps"}}) {
    try {
      const auto v = parse_list(text, key);
      if (!text.empty() && (v.size() < 2 || !std::is_sorted(v.begin(), v.end()) || std::adjacent_find(v.begin(), v.end()) != v.end())) {
        return str_cat("option '", key, "': at least two strictly increasing values");
      }
    } catch (const Error& e) {
      return e.what();
    }
  }
  return BayesFitOptions::validate();
}

std::vector<Term> HybridOptions::terms() const {
  std::vector<Term> t{bias_term()};
  if (bias_order > 0) {
    std::vector<int> orders;
    for (int k = 1; k <= bias_order; ++k) orders.push_back(k);
    t.push_back(temperature_polynomial(orders));
  }
  if (!surface_temperatures_c.empty()) {
    t.push_back(scale_factor_surface(parse_list(surface_temperatures_c, "surface_temperatures_c"), parse_list(surface_rates_dps, "surface_rates_dps")));
  } else {
    ScaleFactorPolynomial::Orders sf;
    for (int i = 0; i <= sf_temperature_order; ++i)
      for (int j = 0; j <= sf_rate_order; ++j) sf.push_back({i, j});
    t.push_back(scale_factor_polynomial(sf));
  }
  if (asymmetry) t.push_back(asymmetry_term());
  return t;
}

namespace {

// A column is determined when more than this share of its norm lies outside the span of the ones kept before it.
constexpr double kIndependentShare = 1e-6;

// The physics terms restricted to what the recording determines, and what was left out and why.
struct IdentifiedPhysics {
  std::vector<Term> terms;
  std::vector<std::string> left_out;  // column names
  std::string note;                   // empty when nothing was left out
};

// The columns are taken in the terms' order (bias, its temperature polynomial, the scale factor by rising
// orders), each kept when more than kIndependentShare of it lies outside the span of those kept before it
// (Gram-Schmidt, twice). An input the recording holds (held_inputs.h) is set to its mean for this test, so its
// higher orders fall on the lower ones: a thermal soak at rest keeps no scale factor, a rate table at one
// temperature no temperature terms, a table at three rates no u^2 beside u^0 (at u = 0, +-1 they agree).
IdentifiedPhysics identified_physics(const std::vector<Term>& terms, const Signals& s, const TermScaling& scaling) {
  const HeldInputs held = held_inputs(s.rate, s.temp_c);
  Signals test = s;
  if (held.temperature) test.temp_c.setConstant(s.temp_c.mean());
  if (held.rate) test.rate.setConstant(s.rate.mean());
  const CoilTemperature coil{test.temp_c, Eigen::VectorXd::Zero(s.size())};  // steady state, as HybridModel
  Eigen::MatrixXd basis(s.size(), 0);
  IdentifiedPhysics out;
  for (const Term& term : terms) {
    const Eigen::MatrixXd c = term_columns(term, test, coil, scaling);
    const std::vector<std::string> names = term.column_names();
    std::vector<int> kept;
    std::vector<std::string> dropped;
    for (int k = 0; k < term.size(); ++k) {
      Eigen::VectorXd r = c.col(k);
      for (int pass = 0; pass < 2; ++pass) r -= basis * (basis.transpose() * r);
      if (r.norm() > kIndependentShare * c.col(k).norm()) {
        kept.push_back(k);
        basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
        basis.rightCols(1) = r / r.norm();
      } else {
        dropped.push_back(names[static_cast<std::size_t>(k)]);
      }
    }
    const std::optional<Term> restricted = term.subset(kept);
    if (restricted && restricted->size() != static_cast<int>(kept.size())) {
      fail("hybrid: the recording does not determine every column of the ", term.kind(), " term (",
           join(dropped), "); give a grid the recording covers, or leave the surface out");
    }
    if (restricted) out.terms.push_back(*restricted);
    out.left_out.insert(out.left_out.end(), dropped.begin(), dropped.end());
  }
  if (!out.left_out.empty()) out.note = held.left_out_note(out.left_out);
  return out;
}

}  // namespace

std::unique_ptr<HybridModel> fit_hybrid(const Recording& recording, const HybridOptions& o, SolveSummary& summary) {
  const Dataset d = make_dataset(recording, default_features(), ModelTarget::error);
  if (!d.reference.allFinite()) fail("hybrid: the training recording has no reference rate (ref_rate_dps)");
  // The physics is defined on the true rate (as the sensor model is): train on (reference rate, temperature).
  Eigen::MatrixXd wt(d.size(), 2);
  wt.col(0) = d.reference, wt.col(1) = d.x.col(1);
  RbfNetwork rbf(default_features(), ModelTarget::error, Normalizer::make(NormalizationKind::range, default_features(), wt));
  Signals s;
  s.t_s = d.t_s, s.rate = wt.col(0), s.temp_c = wt.col(1);
  const TermScaling scaling = TermScaling::of(s);
  const IdentifiedPhysics physics = identified_physics(o.terms(), s, scaling);
  const std::vector<Term>& terms = physics.terms;
  const HybridModel structure(scaling, terms, Eigen::VectorXd::Zero([&] {
    Eigen::Index c = 0;
    for (const auto& t : terms) c += t.size();
    return c;
  }()), rbf, std::nullopt);

  BayesProblem p;
  const double rms = std::sqrt(d.target.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, d.size())));
  const double y_scale = rms > 0 ? rms : 1.0;
  p.x = rbf.normalizer.apply(wt);
  p.y = d.target / y_scale;
  p.fixed = structure.physics_columns(wt.col(0), wt.col(1));
  p.t_s = d.t_s;
  p.report_scale = units::radps_to_dph(y_scale);
  if (o.noise == "given") p.given_noise = given_noise_model(o, median_sample_interval(p.t_s), y_scale);
  BayesFit f;
  summary = timed_solve("hybrid", [&](SolveMonitor& monitor) {
    f = fit_bayes(p, o, monitor);
    nlohmann::json details = f.details(y_scale);
    details["physics_columns"] = p.fixed.cols();
    FitNotes notes;
    notes.nodes = static_cast<int>(f.centres.rows());
    if (!physics.note.empty()) notes.physics_left_out = PhysicsLeftOut{physics.left_out, physics.note};
    write_fit_notes(notes, details);
    return SolveOutcome{f.termination, f.message, details};
  });
  const Eigen::Index m = f.centres.rows();
  rbf.centres = f.centres;
  rbf.widths = f.widths.replicate(m, 1);
  rbf.weights = f.rbf_weights * y_scale;
  WeightPosterior posterior = WeightPosterior::of_covariance(f.covariance * (y_scale * y_scale), f.noise_sigma * y_scale);
  if (f.noise) posterior.noise_model = scaled(*f.noise, units::radps_to_dph(y_scale)).to_json();
  posterior.model_error_radps = std::sqrt(f.model_error_var) * y_scale;
  return std::make_unique<HybridModel>(scaling, terms, f.fixed_weights * y_scale, std::move(rbf), std::move(posterior));
}

}  // namespace gyrosid
