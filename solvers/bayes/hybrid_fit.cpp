#include "solvers/bayes/hybrid_fit.h"

#include "core/error.h"
#include "core/recording.h"
#include "core/units.h"
#include "model/dataset.h"
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
  const std::vector<Term> terms = o.terms();
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
    return SolveOutcome{f.termination, f.message, details};
  });
  summary.details["nodes"] = f.centres.rows();
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
