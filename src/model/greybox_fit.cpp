#include "model/greybox_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <cmath>
#include <algorithm>
#include <functional>
#include <map>

#include "core/bounded_search.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/fit_notes.h"
#include "model/greybox_prior.h"
#include "model/held_inputs.h"
#include "model/surface_comparison.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {

std::string GreyboxOptions::validate() const {
  if (bias_order < 0 || bias_order > 8) return str_cat("bias_order = ", bias_order, " must be in [0, 8]");
  if (sf_temperature_order < 0 || sf_temperature_order > 6) return "sf_temperature_order must be in [0, 6]";
  if (sf_rate_order < 0 || sf_rate_order > 10) return "sf_rate_order must be in [0, 10]";
  if (scale_factor == ScaleFactorForm::surface && (surface_temperatures_c.size() < 2 || surface_rates_dps.size() < 2)) {
    return "surface grids need at least two temperatures and two rates";
  }
  if (!(lag_max_s > 1.0)) return "lag_max_s must exceed 1 s";
  if (!(ridge >= 0 && ridge < 1)) return "ridge must be in [0, 1)";
  return "";
}

std::vector<std::string> greybox_features(const GreyboxOptions& o) {
  std::vector<std::string> f{"measured_rate", "temperature"};
  if (o.g_sensitivity) {
    for (const char* a : {"accel_x_mps2", "accel_y_mps2", "accel_z_mps2"}) f.emplace_back(a);
  }
  return f;
}

std::vector<Term> greybox_terms(const GreyboxOptions& o) {
  std::vector<Term> terms{bias_term()};
  if (o.bias_order > 0) {
    std::vector<int> orders;
    for (int k = 1; k <= o.bias_order; ++k) orders.push_back(k);
    terms.push_back(temperature_polynomial(orders));
  }
  if (o.scale_factor == ScaleFactorForm::surface) {
    terms.push_back(scale_factor_surface(o.surface_temperatures_c, o.surface_rates_dps));
  } else {
    ScaleFactorPolynomial::Orders sf;  // separable: eps_T(T) from the first order, eps(omega) from the zeroth
    for (int i = 1; i <= o.sf_temperature_order; ++i) sf.push_back({i, 0});
    for (int j = 0; j <= o.sf_rate_order; ++j) sf.push_back({0, j});
    terms.push_back(scale_factor_polynomial(sf));
  }
  if (o.shupe) terms.push_back(shupe_term());
  if (o.asymmetry) terms.push_back(asymmetry_term());
  if (o.g_sensitivity) terms.push_back(channel_term({"accel_x_mps2", "accel_y_mps2", "accel_z_mps2"}));
  return terms;
}

GreyboxCoefficients::GreyboxCoefficients(const GreyboxOptions& o) {
  SpanPacker pack;
  bias = pack.take(o.bias_order + 1);
  const bool surface_form = o.scale_factor == ScaleFactorForm::surface;
  sf_temperature = pack.take_if(!surface_form, o.sf_temperature_order);
  sf_rate = pack.take_if(!surface_form, o.sf_rate_order + 1);
  surface = pack.take_if(surface_form, static_cast<Eigen::Index>(o.surface_temperatures_c.size() * o.surface_rates_dps.size()));
  shupe = pack.take_if(o.shupe, 1);
  asymmetry = pack.take_if(o.asymmetry, 1);
  g_sensitivity = pack.take_if(o.g_sensitivity, 3);
  size = pack.size();
}

namespace {

// The recording as term inputs: the physics acts on the true (reference) rate.
Signals signals_of(const Dataset& d) {
  Signals s;
  s.t_s = d.t_s;
  s.rate = d.reference;
  s.temp_c = d.x.col(1);
  for (std::size_t f = 2; f < d.features.size(); ++f) s.channels[d.features[f]] = d.x.col(static_cast<Eigen::Index>(f));
  return s;
}

// (S'S)^-1 of a full-rank stacked matrix S = [rows] D^-1 on unit-norm columns, back in unscaled coefficients.
Eigen::MatrixXd inverse_gram(const Eigen::MatrixXd& scaled, const Eigen::VectorXd& norm) {
  const Eigen::Index p = scaled.cols();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(scaled);
  const Eigen::MatrixXd r = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_inv = r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::MatrixXd d_inv = norm.cwiseInverse().asDiagonal();
  return d_inv * (r_inv * r_inv.transpose()) * d_inv;
}

// Ridge-regularised least squares by pivoted QR on unit-norm columns; the RSS into *rss, (A'A + ridge)^-1
// (unit noise) into *covariance on request.
Eigen::VectorXd ridge_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, double ridge, double* rss, Eigen::MatrixXd* covariance = nullptr) {
  const Eigen::Index n = a.rows(), p = a.cols();
  const Eigen::VectorXd norm = a.colwise().norm().transpose().cwiseMax(1e-300);
  Eigen::MatrixXd aug(n + p, p);
  aug.topRows(n) = a * norm.cwiseInverse().asDiagonal();
  aug.bottomRows(p) = std::sqrt(ridge) * Eigen::MatrixXd::Identity(p, p);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + p);
  rhs.head(n) = y;
  const Eigen::VectorXd coeff = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(aug).solve(rhs).cwiseQuotient(norm);
  if (rss) *rss = (a * coeff - y).squaredNorm();
  if (covariance) *covariance = inverse_gram(aug, norm);
  return coeff;
}

// The prior as rows on the coefficients, L^-1 M c ~ L^-1 mu_c (Sigma_c = L L'), and the lag's marginal.
struct PriorRows {
  Eigen::MatrixXd rows;
  Eigen::VectorXd rhs;
  double lag_mean = 0.0, lag_variance = 0.0;
};

PriorRows prior_rows(const GreyboxPrior& prior, const Eigen::MatrixXd& m, bool lag) {
  const Eigen::Index q = m.rows();
  const Eigen::LLT<Eigen::MatrixXd> llt(prior.covariance.topLeftCorner(q, q));
  if (llt.info() != Eigen::Success) fail("grey-box prior", prior.source.empty() ? "" : " (" + prior.source + ")", ": the covariance is not positive definite");
  PriorRows r{llt.matrixL().solve(m), llt.matrixL().solve(prior.mean.head(q))};
  if (lag) r.lag_mean = prior.mean(q), r.lag_variance = prior.covariance(q, q);
  return r;
}

// (S'S)^-1 from the column-pivoted QR S Pi = Q R of a full-rank S = [rows] D^-1 on unit-norm columns:
// S'S = Pi R'R Pi', so (S'S)^-1 = (Pi R^-1)(Pi R^-1)' (no normal equations), then D^-1 (.) D^-1 for the
// unscaled coefficients.
Eigen::MatrixXd inverse_gram(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, const Eigen::VectorXd& norm) {
  const Eigen::Index p = qr.cols();
  const Eigen::MatrixXd r_inv = qr.matrixR().topLeftCorner(p, p).triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::MatrixXd root = norm.cwiseInverse().asDiagonal() * (qr.colsPermutation() * r_inv);
  return root * root.transpose();
}

// The MAP of the linear part: [a / s; B] c = [y / s; b] by pivoted QR on unit-norm columns. Returns the
// objective |a c - y|^2 / s^2 + |B c - b|^2; the coefficients into *c and, on request, their posterior
// covariance (a'a / s^2 + B'B)^-1 from the same factorisation (Bishop, PRML eqs 3.50-3.51, with the prior's
// rows B = L^-1 M in place of its precision).
double map_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, double s, const PriorRows& prior, Eigen::VectorXd* c,
                 Eigen::MatrixXd* covariance = nullptr) {
  const Eigen::Index n = a.rows(), p = a.cols(), q = prior.rows.rows();
  const Eigen::VectorXd norm = (a.colwise().squaredNorm() / (s * s) + prior.rows.colwise().squaredNorm()).cwiseSqrt().transpose().cwiseMax(1e-300);
  Eigen::MatrixXd stacked(n + q, p);
  stacked.topRows(n) = a * (norm.cwiseInverse() / s).asDiagonal();
  stacked.bottomRows(q) = prior.rows * norm.cwiseInverse().asDiagonal();
  Eigen::VectorXd rhs(n + q);
  rhs.head(n) = y / s;
  rhs.tail(q) = prior.rhs;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(stacked);
  *c = qr.solve(rhs).cwiseQuotient(norm);
  if (covariance) *covariance = inverse_gram(qr, norm);
  return (a * *c - y).squaredNorm() / (s * s) + (prior.rows * *c - prior.rhs).squaredNorm();
}

// The coefficients, in greybox_terms' order, as the sensor layer's error model (SI, unscaled).
GyroErrorModel error_model_of(const GreyboxOptions& o, const TermScaling& sc, const Eigen::VectorXd& c) {
  const GreyboxCoefficients at(o);
  GyroErrorModel e;
  e.bias_temperature_radps.reference = sc.t_ref_c;
  for (int i = 0; i <= o.bias_order; ++i) e.bias_temperature_radps.coefficients.push_back(c(at.bias.at(i)) / std::pow(sc.t_scale_c, i));
  if (o.scale_factor == ScaleFactorForm::surface) {
    const auto nt = static_cast<Eigen::Index>(o.surface_temperatures_c.size()), nw = static_cast<Eigen::Index>(o.surface_rates_dps.size());
    const Eigen::MatrixXd v = at.surface.of(c).reshaped<Eigen::RowMajor>(nt, nw);
    std::vector<double> rates;
    for (double r : o.surface_rates_dps) rates.push_back(units::dps_to_radps(r));
    e.scale_factor_surface = SplineSurface(o.surface_temperatures_c, rates, v, OutsideGridPolicy::clamp);
  } else {
    e.scale_factor_temperature.reference = sc.t_ref_c;
    e.scale_factor_temperature.coefficients.push_back(0.0);
    for (int i = 1; i <= o.sf_temperature_order; ++i) e.scale_factor_temperature.coefficients.push_back(c(at.sf_temperature.at(i - 1)) / std::pow(sc.t_scale_c, i));
    for (int i = 0; i <= o.sf_rate_order; ++i) e.scale_factor_rate.coefficients.push_back(c(at.sf_rate.at(i)) / std::pow(sc.rate_scale_radps, i));
  }
  if (o.shupe) e.shupe_rad_per_c = c(at.shupe.offset);
  if (o.asymmetry) e.scale_factor_asymmetry = 2.0 * c(at.asymmetry.offset);  // the column is |w| = (a/2)^-1 of dSF's jump
  if (o.g_sensitivity) e.g_sensitivity = at.g_sensitivity.of(c);
  return e;
}

struct LagSearch {
  double tau_s = 0.0;
  int evaluations = 0;
  SolveOutcome outcome{Termination::converged, "linear least squares by column-pivoted QR with a ridge", {}};
};

// The lag by a coarse log grid of tau over [1 s, lag_max] (tau = 0 included), then BOBYQA on log tau.
LagSearch search_lag(const std::function<double(double)>& rss_at, const GreyboxOptions& o) {
  LagSearch s;
  double best_rss = rss_at(0.0), best_log = -INFINITY;
  const double lo = 0.0, hi = std::log(o.lag_max_s);
  for (int i = 0; i <= 12; ++i) {
    const double lt = lo + (hi - lo) * i / 12.0;
    const double r = rss_at(std::exp(lt));
    if (r < best_rss) best_rss = r, best_log = lt;
  }
  s.evaluations = 14;
  if (!std::isfinite(best_log)) {
    s.outcome.message = "no lag: tau = 0 fits better than every grid value";
    return s;
  }
  BoundedSearchOptions bobyqa;
  bobyqa.xtol_abs = 1e-4;
  bobyqa.max_evaluations = 60;
  const BoundedSearchResult r = minimize_bounded([&](const std::vector<double>& x) { return rss_at(std::exp(x[0])); }, {best_log}, {lo}, {hi},
                                                 bobyqa);
  s.evaluations += r.evaluations;
  s.tau_s = r.value <= best_rss ? std::exp(r.x[0]) : std::exp(best_log);
  s.outcome = {termination_of(r), "lag by BOBYQA on log tau: " + r.message, {}};
  return s;
}

// 1 - posterior / prior variance, averaged over each group of coordinates (the lag apart).
std::vector<std::pair<std::string, double>> data_share(const GreyboxOptions& o, const Eigen::MatrixXd& posterior, const GreyboxPrior& prior) {
  std::map<std::string, std::pair<double, int>> sum;
  const auto coordinates = greybox_coordinates(o);
  for (Eigen::Index i = 0; i < posterior.rows(); ++i) {
    if (coordinates[static_cast<std::size_t>(i)].group == "lag") continue;  // searched, not estimated with a variance
    auto& [share, count] = sum[coordinates[static_cast<std::size_t>(i)].group];
    share += std::clamp(1.0 - posterior(i, i) / prior.covariance(i, i), 0.0, 1.0);
    ++count;
  }
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [group, sc] : sum) out.emplace_back(group, sc.first / sc.second);
  return out;
}

}  // namespace

Eigen::MatrixXd greybox_theta_map(const GreyboxOptions& o, const TermScaling& sc) {
  GreyboxOptions linear = o;
  linear.thermal_lag = false;
  const Eigen::Index p = total_columns(greybox_terms(o));
  Eigen::MatrixXd m(static_cast<Eigen::Index>(greybox_coordinates(linear).size()), p);
  for (Eigen::Index j = 0; j < p; ++j) m.col(j) = greybox_theta(error_model_of(o, sc, Eigen::VectorXd::Unit(p, j)), 0.0, linear);
  return m;
}

namespace {

void check_inputs(const Dataset& data, const GreyboxOptions& o, const GreyboxPrior* prior) {
  if (auto p = o.validate(); !p.empty()) fail("greybox model: ", p);
  if (data.features != greybox_features(o)) {
    fail("greybox model: features must be ", join(greybox_features(o)));
  }
  if (!data.target.allFinite()) fail("greybox model: the recording has no reference rate (ref_rate_dps) to fit against");
  if (prior) {
    if (auto p = prior->validate(o); !p.empty()) fail("greybox model with a prior", prior->source.empty() ? "" : " (" + prior->source + ")", ": ", p);
  }
}

// theta's covariance M C M' of coefficients with covariance C, the lag's row and column 0.
Eigen::MatrixXd theta_covariance_of(const Eigen::MatrixXd& m, const Eigen::MatrixXd& covariance, bool lag) {
  const Eigen::Index q = m.rows(), lag_row = lag ? 1 : 0;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(q + lag_row, q + lag_row);
  out.topLeftCorner(q, q) = m * covariance * m.transpose();
  return out;
}

// The predictive sigma of a model with a posterior over the nodes of its surface grid (deg/h): what a user
// reads to see where the prior filled in.
PredictiveSigma predictive_sigma(const CalibrationModel& model, const GreyboxOptions& o) {
  const SigmaMap map = predictive_sigma_map(model, o.surface_temperatures_c, o.surface_rates_dps);
  return {map.rms_dph, map.max_dph, map.max_temp_c, map.max_rate_dps};
}

GreyboxEstimate estimate(const Dataset& data, const GreyboxOptions& o, const GreyboxPrior* prior, SolveSummary* summary, bool want_covariance) {
  check_inputs(data, o, prior);
  const Signals s = signals_of(data);
  const TermScaling scaling = TermScaling::of(s);
  const std::vector<Term> terms = greybox_terms(o);
  const int p = total_columns(terms);
  if (data.size() < 2 * p) fail("greybox model: ", data.size(), " samples for ", p, " coefficients");
  const auto a_at = [&](double tau) { return design_matrix(terms, s, coil_temperature(s, tau), scaling); };

  GreyboxEstimate out;
  SolveSummary result = timed_solve(prior ? "greybox (prior)" : "greybox", [&](SolveMonitor& monitor) {
    // Without a prior: least squares with a ridge. With one: the noise level of that fit at the prior's lag, then the MAP.
    const Eigen::MatrixXd m = prior || want_covariance ? greybox_theta_map(o, scaling) : Eigen::MatrixXd();
    const PriorRows rows = prior ? prior_rows(*prior, m, o.thermal_lag) : PriorRows{};
    const auto sd_of = [&](double rss) { return std::sqrt(rss / static_cast<double>(data.size() - p)); };
    double sd = 0.0;
    if (prior) {
      double rss = 0.0;
      ridge_solve(a_at(o.thermal_lag ? std::max(0.0, rows.lag_mean) : 0.0), data.target, o.ridge, &rss);
      sd = sd_of(rss);
    }
    auto cost_at = [&](double tau) {
      double cost = 0.0;
      Eigen::VectorXd c;
      if (prior) {
        cost = map_solve(a_at(tau), data.target, sd, rows, &c) + (o.thermal_lag ? std::pow(tau - rows.lag_mean, 2) / rows.lag_variance : 0.0);
      } else {
        ridge_solve(a_at(tau), data.target, o.ridge, &cost);
      }
      monitor.iteration(0.5 * cost);
      monitor.evaluation();
      return cost;
    };
    LagSearch lag;
    if (o.thermal_lag) lag = search_lag(cost_at, o);
    const Eigen::MatrixXd a = a_at(lag.tau_s);
    Eigen::VectorXd c;
    Eigen::MatrixXd covariance;
    std::optional<GreyboxPosterior> posterior;  // with a prior: the coefficients' at the found lag, noise s
    double rss = 0.0;
    if (prior) {
      const double cost = map_solve(a, data.target, sd, rows, &c, &covariance);
      rss = (a * c - data.target).squaredNorm();
      if (!o.thermal_lag) monitor.iteration(0.5 * cost), monitor.evaluation();
      lag.outcome.message = "maximum a posteriori under the prior " + prior->source + ": linear least squares by column-pivoted QR";
      if (c.allFinite()) posterior = GreyboxPosterior{scaling, terms, c, WeightPosterior::of_covariance(covariance, sd)};
    } else {
      c = ridge_solve(a, data.target, o.ridge, &rss, want_covariance ? &covariance : nullptr);
      sd = sd_of(rss);
      covariance *= sd * sd;
      if (!o.thermal_lag) monitor.iteration(0.5 * rss), monitor.evaluation();
    }
    if (!c.allFinite()) lag.outcome = {Termination::failed, "the linear solve gave non-finite coefficients", {}};
    out.model = std::make_unique<GreyboxModel>(data.features, error_model_of(o, scaling, c), lag.tau_s, std::move(posterior));
    out.residual_sd_radps = sd;
    lag.outcome.details = {{"samples", data.size()},
                           {"rms_residual_dph", units::radps_to_dph(std::sqrt(rss / static_cast<double>(data.size())))},
                           {"lag_tau_s", lag.tau_s},
                           {"lag_evaluations", o.thermal_lag ? lag.evaluations : 0}};
    if (covariance.size() > 0) out.theta_covariance = theta_covariance_of(m, covariance, o.thermal_lag);
    FitNotes notes;
    notes.parameters = p + (o.thermal_lag ? 1 : 0);
    if (prior) {
      lag.outcome.details["prior"] = prior->source;
      notes.data_share = data_share(o, out.theta_covariance, *prior);
    }
    if (const HeldInputs held = held_inputs(s.rate, s.temp_c); held.temperature || held.rate) notes.physics_note = held.ridge_note();
    write_fit_notes(notes, lag.outcome.details);
    return lag.outcome;
  });
  if (out.model->posterior()) {
    FitNotes notes;
    notes.predictive_sigma = predictive_sigma(*out.model, o);
    write_fit_notes(notes, result.details);
  }
  if (want_covariance) out.theta = greybox_theta(out.model->errors(), out.model->lag_tau_s(), o);
  if (summary) *summary = result;
  return out;
}

}  // namespace

GreyboxEstimate estimate_greybox(const Dataset& data, const GreyboxOptions& o, const GreyboxPrior* prior, SolveSummary* summary) {
  return estimate(data, o, prior, summary, true);
}

std::unique_ptr<GreyboxModel> fit_greybox(const Dataset& data, const GreyboxOptions& o, SolveSummary* summary) {
  return estimate(data, o, nullptr, summary, false).model;
}

}  // namespace gyrosid
