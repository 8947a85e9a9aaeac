#include "design/assessment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/units.h"
#include "design/evidence_network.h"

namespace gyrosid::design {
namespace {

// Prior standard deviations: each column group scaled so that its prior predictive RMS over the domain
// equals kappa times the sensor's RMS error there. For the RBF proxy (kappa = 1) the prior is the network's
// regularisation; the physics models are fitted by plain least squares (their fits' ridge is 1e-9), so their
// prior (kappa = 1000) only keeps the directions no sample determines finite - a design that leaves them
// undetermined is charged what a least-squares fit would do there. The hybrid's network (a residual group)
// is scaled to what its physics, fitted to the sensor's error over the domain, leaves: the evidence sets the
// network's prior on that residual. The named effects get their physical magnitudes (a plain fit has them
// too, the grey-box fit with its effect terms switched on).
// The regressor's column indices with a flat prior (the physics) and with the learned one (the network).
struct ColumnsByPrior {
  std::vector<Eigen::Index> flat, learned;
};
ColumnsByPrior columns_by_prior(const Regressor& r) {
  const std::vector<int> groups = r.groups(), learned = r.residual_groups();
  ColumnsByPrior out;
  for (std::size_t j = 0; j < groups.size(); ++j) {
    const bool is_learned = std::find(learned.begin(), learned.end(), groups[j]) != learned.end();
    (is_learned ? out.learned : out.flat).push_back(static_cast<Eigen::Index>(j));
  }
  return out;
}

Eigen::VectorXd prior_scales(const Regressor& r, ModelFamily family, const ModelOptions& o, const Domain& domain,
                             const GyroErrorModel& truth, const NetworkNodes* network) {
  const SteadyGrid grid = steady_grid(domain, truth);
  const auto rms_of = [](const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, v.size()))); };
  const double rms = std::max(rms_of(grid.true_error), units::dph_to_radps(1.0));
  const double kappa = family == ModelFamily::rbf ? 1.0 : 1000.0;
  const Eigen::MatrixXd a = r.columns(grid.inputs);
  const std::vector<int> groups = r.groups(), learned = r.residual_groups();
  const auto is_learned = [&](int g) { return std::find(learned.begin(), learned.end(), g) != learned.end(); };
  // What the groups with a flat prior leave of the sensor's error (column-pivoted QR: rank-safe).
  double residual_rms = rms;
  if (!learned.empty()) {
    const Eigen::MatrixXd f = a(Eigen::all, columns_by_prior(r).flat);
    const Eigen::VectorXd fit = f * f.colPivHouseholderQr().solve(grid.true_error);
    residual_rms = std::max(rms_of(grid.true_error - fit), 1e-3 * rms);
  }
  Eigen::VectorXd s(r.size());
  for (int g = 0; g <= *std::max_element(groups.begin(), groups.end()); ++g) {
    double power = 0.0;
    for (std::size_t j = 0; j < groups.size(); ++j) {
      if (groups[j] == g) power += a.col(static_cast<Eigen::Index>(j)).squaredNorm() / static_cast<double>(a.rows());
    }
    const double target = is_learned(g) ? o.network_prior_scale * residual_rms : kappa * rms;
    // A network chosen by the expected evidence brings its own prior: 1 / sqrt(alpha) on every weight.
    const double scale = is_learned(g) && network ? network->prior_sd_radps : target / (power > 0 ? std::sqrt(power) : 1.0);
    for (std::size_t j = 0; j < groups.size(); ++j) {
      if (groups[j] == g) s(static_cast<Eigen::Index>(j)) = scale;
    }
  }
  for (const auto& [name, j] : r.effects()) {
    if (name == "shupe") s(j) = units::dph_to_radps(o.shupe_prior_dph_per_c_per_min) * 60.0;
    else if (name == "hysteresis") s(j) = units::dph_to_radps(o.hysteresis_prior_dph);
    else if (name == "thermal_lag") s(j) = o.thermal_lag_prior_s;
  }
  return s;
}

// The grey-box calibration's prior when it fits with a lot's (ModelOptions::calibration_prior): the population
// N(mu, Sigma) over the coordinates theta_lin = M c (model/greybox_prior.h) is N(M^-1 mu, M^-1 L (M^-1 L)'),
// Sigma = L L', on the regressor's coefficients - its terms are the fit's, on the domain's scaling, so M is
// square - and the lag's marginal on the lag column, which is linearised about the sensor's own tau (the fit
// also takes the lag's prior marginally). The other columns (hysteresis) keep `scales`.
Prior calibration_prior(const Eigen::VectorXd& scales, const Regressor& r, const ModelOptions& o, const Domain& d, double coil_tau_s) {
  const GreyboxPrior& lot = *o.calibration_prior;
  GreyboxOptions g = greybox_options(o, d);
  g.thermal_lag = o.thermal_lag;
  const auto refuse = [&](const std::string& why) { fail("design: the calibration's prior (", lot.source, ") and the design's grey-box model: ", why); };
  if (auto p = lot.validate(g); !p.empty()) refuse(p);
  const Eigen::MatrixXd m = greybox_theta_map(g, domain_scaling(d));
  const Eigen::Index q = m.rows();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(m);
  if (m.cols() != q || qr.rank() < q) refuse("the coordinates do not determine the coefficients");
  const Eigen::LLT<Eigen::MatrixXd> llt(lot.covariance.topLeftCorner(q, q));
  if (llt.info() != Eigen::Success) refuse("the prior's covariance is not positive definite");
  Prior p = Prior::independent(scales);
  p.mean.head(q) = qr.solve(lot.mean.head(q));
  p.root.topLeftCorner(q, q) = qr.solve(Eigen::MatrixXd(llt.matrixL()));
  for (const auto& [name, j] : r.effects()) {
    if (name == "thermal_lag") p.mean(j) = lot.mean(q) - coil_tau_s, p.root(j, j) = std::sqrt(lot.covariance(q, q));
  }
  return p;
}

struct EffectUnit {
  const char* unit;
  double per_si;  // multiply an SI value by this
};
EffectUnit effect_unit(const std::string& name) {
  if (name == "shupe") return {"deg/h per C/min", units::radps_to_dph(1.0) / 60.0};
  if (name == "hysteresis") return {"deg/h", units::radps_to_dph(1.0)};
  return {"s", 1.0};
}

}  // namespace

double expected_norm(const Eigen::Vector3d& mean, const Eigen::Matrix3d& cov) {
  // |y| = pi^-1/2 int_0^inf (1 - exp(-s^2 |y|^2)) s^-2 ds, and for y ~ N(m, C) with C = V diag(l) V',
  // E exp(-s^2 |y|^2) = prod_i (1 + 2 s^2 l_i)^-1/2 exp(-s^2 sum_i (V'm)_i^2 / (1 + 2 s^2 l_i)):
  // a smooth one-dimensional integral, by the trapezoidal rule in log s (spectrally accurate here).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (cov + cov.transpose()));
  const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);
  const Eigen::Vector3d m2 = (eig.eigenvectors().transpose() * mean).cwiseAbs2();
  const double scale = std::sqrt(l.sum() + m2.sum());
  if (!(scale > 0)) return 0.0;
  const double h = 0.02;
  double sum = 0.0;
  for (double u = -25.0; u <= 25.0; u += h) {
    const double s2 = std::exp(2.0 * u) / (scale * scale);
    double log_phi = 0.0;
    for (int i = 0; i < 3; ++i) log_phi -= 0.5 * std::log1p(2.0 * s2 * l(i)) + s2 * m2(i) / (1.0 + 2.0 * s2 * l(i));
    sum += -std::expm1(log_phi) / std::sqrt(s2);  // (1 - phi) / s^2 * ds, ds = s du
  }
  return sum * h / std::sqrt(std::numbers::pi);
}

DesignContext::DesignContext(const SensorSpec& sensor, std::shared_ptr<const Envelope> envelope, ModelFamily family,
                             const ModelOptions& model, Criterion criterion, const Domain& model_domain,
                             std::shared_ptr<const NetworkNodes> network)
    : sensor_(sensor), triad_(as_triad(sensor)), envelope_(std::move(envelope)), family_(family), model_(model),
      criterion_(criterion), model_domain_(model_domain), noise_(NoiseSpec::of(triad_.gyros[2].noise)), network_(std::move(network)) {
  if (!noise_.any()) fail("design: sensor '", sensor_name(sensor), "' has no noise; a design minimises the noise-driven calibration error");
  if (network_ && family != ModelFamily::hybrid) fail("design: a fitted network is for the hybrid model");
  regressor_ = make_regressor(family, model, model_domain_, gyro().errors, thermal().coil_tau_s, network_.get());
  if ((criterion == Criterion::effects) && regressor_->effects().empty()) {
    fail("design: criterion 'effects' needs the greybox model with at least one of model.shupe, model.hysteresis, model.thermal_lag");
  }
  if ((criterion == Criterion::cof || criterion == Criterion::cof_minimax) && envelope_->flights.empty()) {
    fail("design: criterion '", to_string(criterion), "' needs flights in the envelope");
  }
  const Eigen::VectorXd scales = prior_scales(*regressor_, family, model, model_domain_, gyro().errors, network_.get());
  prior_ = family == ModelFamily::greybox && model.calibration_prior ? calibration_prior(scales, *regressor_, model, model_domain_, thermal().coil_tau_s)
                                                                     : Prior::independent(scales);
  lin_ = linearise(*envelope_, *regressor_);
  const Eigen::Index p = regressor_->size();
  surface_moment_ = Eigen::MatrixXd::Zero(p, p);
  auto add_moment = [&](const Eigen::MatrixXd& a, double weight) {
    surface_moment_ += weight * a.transpose() * a / static_cast<double>(a.rows());
  };
  if (envelope_->uniform_samples) add_moment(lin_.uniform_columns, 1.0);
  for (const auto& f : lin_.flights) add_moment(f.surface_columns, 1.0 / static_cast<double>(lin_.flights.size()));
  evidence_prior_ = family == ModelFamily::hybrid && !network_ && model.network_prior == "evidence";
}

Eigen::MatrixXd DesignContext::scaled_sensitivity(std::size_t flight, const LinearEstimate& e) const {
  return lin_.flights[flight].sensitivity * e.prior.root;
}

Prior DesignContext::evidence_prior(const Eigen::MatrixXd& w) const {
  // w = whiten([A | e]): the dictionary's prior precision alpha by the expected evidence of the noise-free
  // target along these observations (evidence_network.h), the physics projected off (its prior is flat).
  const ColumnsByPrior cols = columns_by_prior(*regressor_);
  const PhysicsProjection physics_span(w(Eigen::all, cols.flat));
  Eigen::MatrixXd rest(w.rows(), static_cast<Eigen::Index>(cols.learned.size()) + 1);
  rest << w(Eigen::all, cols.learned), w.col(w.cols() - 1);
  physics_span.project(rest);
  const ExpectedEvidence ev(rest.leftCols(rest.cols() - 1), rest.col(rest.cols() - 1), physics_span.residual_dof());
  Prior prior = prior_;
  const double sd = std::exp(-0.5 * ev.best_log_alpha());
  for (Eigen::Index j : cols.learned) prior.root(j, j) = sd;
  return prior;
}

const DesignContext::Anchor& DesignContext::anchor() const {
  // The anchor of the linearised model-class error: the model's least-squares fit to the sensor's error on a
  // steady grid over the domain (a tiny ridge in prior units keeps undetermined directions at the prior mean),
  // and its exact position error per flight.
  std::call_once(anchor_once_, [&] {
    const SteadyGrid grid = steady_grid(model_domain_, gyro().errors);
    const Eigen::MatrixXd al = regressor_->columns(grid.inputs) * prior_.root;
    // Ridge least squares by QR of the stacked system [A L; sqrt(lambda) I] z = [e; 0], not its normal equations.
    const Eigen::Index np = prior_.size();
    const double lambda = 1e-9 * al.squaredNorm() / static_cast<double>(np);
    Eigen::MatrixXd stacked(al.rows() + np, np);
    stacked << al, std::sqrt(lambda) * Eigen::MatrixXd::Identity(np, np);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(al.rows() + np);
    rhs.head(al.rows()) = grid.true_error;
    anchor_.theta = prior_.mean + prior_.root * stacked.colPivHouseholderQr().solve(rhs);
    for (const auto& f : envelope_->flights) anchor_.error.push_back(f.position_error(*regressor_, anchor_.theta));
  });
  return anchor_;
}

std::unique_ptr<DesignContext> DesignContext::derived(const Domain& d, std::shared_ptr<const NetworkNodes> network) const {
  auto c = std::make_unique<DesignContext>(sensor_, envelope_, family_, model_, criterion_, d, std::move(network));
  c->log_reference_ = log_reference_;
  c->reference_cof_m_ = reference_cof_m_;
  c->statistic_ = statistic_;
  return c;
}

std::unique_ptr<DesignContext> DesignContext::with_domain(const Domain& d) const { return derived(d, network_); }

std::unique_ptr<DesignContext> DesignContext::following(const Observations& o) const {
  if (family_ != ModelFamily::hybrid || model_.network != "evidence") return nullptr;
  // The physics' columns along o: the groups with a flat prior (the dictionary's group is the learned one).
  const Eigen::MatrixXd a = regressor_->columns(o.inputs);
  NetworkSearchOptions search;
  search.nodes = model_.network_nodes;
  search.given_widths = model_.given_network_widths();
  search.given_prior_sd_radps = units::dph_to_radps(model_.network_prior_sd_dph);
  return derived(model_domain_, std::make_shared<const NetworkNodes>(
                                    expected_evidence_network(o, a(Eigen::all, columns_by_prior(*regressor_).flat), noise_, search)));
}

void DesignContext::set_reference(const Prediction& reference, ReferenceStatistic statistic) {
  if (reference.flights.size() != envelope_->flights.size()) fail("design: the reference was predicted for other flights");
  statistic_ = statistic;
  log_reference_.clear();
  reference_cof_m_.clear();
  for (const auto& f : reference.flights) {
    reference_cof_m_.push_back(statistic == ReferenceStatistic::mse_noise ? f.cof_noise_mean_m : f.cof_m);
    double r2 = 0.0;
    switch (statistic) {
      case ReferenceStatistic::mse: r2 = f.cof_bias_m * f.cof_bias_m + f.cof_noise_m * f.cof_noise_m; break;
      case ReferenceStatistic::mse_noise: r2 = f.cof_noise_m * f.cof_noise_m; break;
      case ReferenceStatistic::posterior: r2 = f.cof_posterior_m * f.cof_posterior_m; break;
      case ReferenceStatistic::cof: r2 = f.cof_m * f.cof_m; break;
    }
    log_reference_.push_back(std::log(std::max(r2, 1e-300)));
  }
}

double DesignContext::flight_mse(std::size_t flight, const LinearEstimate& e) const {
  if (e.expected.size() != prior_.size()) fail("design: the mean squared criterion needs the estimate's expected value (estimate with its target)");
  if (flight >= envelope_->flights.size()) fail("design: no flight ", flight, " in the envelope");
  const Anchor& a = anchor();
  const Eigen::MatrixXd s = scaled_sensitivity(flight, e);
  const Eigen::Vector3d m = a.error[flight] + lin_.flights[flight].sensitivity * (e.expected_theta() - a.theta);
  return m.squaredNorm() + (s * e.estimator * s.transpose()).trace();
}

LinearEstimate DesignContext::estimate(const Observations& o, bool with_target) const {
  Eigen::MatrixXd a = regressor_->columns(o.inputs);
  if (with_target || evidence_prior_) {
    a.conservativeResize(Eigen::NoChange, a.cols() + 1);
    a.col(a.cols() - 1) = o.true_error;
  }
  const Eigen::MatrixXd w = whiten(a, o.inputs.t_s, o.weight_s, noise_);
  if (!evidence_prior_) return linear_estimate(w, prior_, with_target);
  const Prior prior = evidence_prior(w);
  return with_target ? linear_estimate(w, prior, true) : linear_estimate(w.leftCols(w.cols() - 1), prior, false);
}

double DesignContext::objective(const LinearEstimate& e) const {
  switch (criterion_) {
    case Criterion::cof: {
      double sum = 0.0;
      for (std::size_t f = 0; f < lin_.flights.size(); ++f) {
        const Eigen::MatrixXd s = scaled_sensitivity(f, e);
        sum += std::log((s * e.posterior * s.transpose()).trace());
      }
      return sum / static_cast<double>(lin_.flights.size());
    }
    case Criterion::cof_minimax: return objective(e, {});
    case Criterion::surface: return std::log((e.prior.root.transpose() * surface_moment_ * e.prior.root * e.posterior).trace());
    case Criterion::d_optimal: return -e.log_det_information;
    case Criterion::a_optimal: return std::log(e.posterior.trace());
    case Criterion::effects: {
      double sum = 0.0;
      for (const auto& [name, j] : regressor_->effects()) sum += std::log(e.posterior(j, j));
      return sum;
    }
  }
  fail("design: unknown criterion");
}

std::vector<double> DesignContext::flight_log_ratios(const LinearEstimate& e) const {
  if (log_reference_.size() != lin_.flights.size()) fail("design: criterion 'cof_minimax' needs a reference trajectory");
  std::vector<double> x;
  for (std::size_t f = 0; f < lin_.flights.size(); ++f) {
    double statistic = 0.0;
    if (design_mse()) {
      statistic = flight_mse(f, e);
    } else {
      const Eigen::MatrixXd s = scaled_sensitivity(f, e);
      statistic = (s * e.posterior * s.transpose()).trace();
    }
    x.push_back(std::log(statistic) - log_reference_[f]);
  }
  return x;
}

std::vector<double> DesignContext::flight_log_ratios(const Prediction& p) const {
  if (log_reference_.size() != p.flights.size()) fail("design: the log ratios need a reference on the prediction's flights");
  std::vector<double> x;
  for (std::size_t f = 0; f < p.flights.size(); ++f) {
    const FlightPrediction& fp = p.flights[f];
    const double statistic = design_mse() ? fp.cof_bias_m * fp.cof_bias_m + fp.cof_noise_m * fp.cof_noise_m
                                                                   : fp.cof_posterior_m * fp.cof_posterior_m;
    x.push_back(std::log(statistic) - log_reference_[f]);
  }
  return x;
}

double DesignContext::objective(const LinearEstimate& e, const std::vector<double>& offsets) const {
  if (criterion_ != Criterion::cof_minimax) {
    if (!offsets.empty()) fail("design: per-flight offsets are for criterion 'cof_minimax'");
    return objective(e);
  }
  std::vector<double> x = flight_log_ratios(e);
  if (!offsets.empty() && offsets.size() != x.size()) fail("design: ", offsets.size(), " flight offsets for ", x.size(), " flights");
  for (std::size_t f = 0; f < offsets.size(); ++f) x[f] += offsets[f];
  // log-sum-exp with sharpness k: within 1/k log(F) of the worst flight's log ratio, smooth.
  constexpr double k = 8.0;
  const double worst = *std::max_element(x.begin(), x.end());
  double sum = 0.0;
  for (double v : x) sum += std::exp(k * (v - worst));
  return worst + std::log(sum) / k;
}

Prediction DesignContext::predict(const Observations& o) const {
  const LinearEstimate e = estimate(o, true);
  Prediction p;
  if (network_) p.network = *network_;
  p.criterion = criterion_;
  p.objective = objective(e);
  p.observations = static_cast<std::size_t>(o.size());
  p.duration_min = o.weight_s.sum() / 60.0;
  const Eigen::VectorXd theta = e.expected_theta();
  const Eigen::MatrixXd sigma = e.estimator_covariance();
  auto surface = [&](const Eigen::MatrixXd& a, const Eigen::VectorXd& truth, double* bias_dph, double* noise_dph) {
    const Eigen::VectorXd bias = truth - a * theta;
    const double var = (a * sigma).cwiseProduct(a).sum() / static_cast<double>(a.rows());
    *bias_dph = units::radps_to_dph(std::sqrt(bias.squaredNorm() / static_cast<double>(a.rows())));
    *noise_dph = units::radps_to_dph(std::sqrt(var));
    return std::hypot(*bias_dph, *noise_dph);
  };
  for (std::size_t i = 0; i < lin_.flights.size(); ++i) {
    const FlightEnvelope& f = envelope_->flights[i];
    const FlightLinearisation& lin = lin_.flights[i];
    FlightPrediction fp;
    fp.flight = f.name;
    fp.horizon_s = f.horizon_s;
    const Eigen::Vector3d m = f.position_error(*regressor_, theta);
    const Eigen::Matrix3d c = lin.sensitivity * sigma * lin.sensitivity.transpose();
    fp.cof_m = expected_norm(m, c);
    fp.cof_noise_m = std::sqrt(c.trace());
    fp.cof_noise_mean_m = expected_norm(Eigen::Vector3d::Zero(), c);
    fp.cof_bias_m = m.norm();
    fp.bias_ned_m = m;
    fp.noise_covariance_ned_m2 = c;
    const Eigen::MatrixXd scaled = scaled_sensitivity(i, e);
    fp.cof_posterior_m = std::sqrt((scaled * e.posterior * scaled.transpose()).trace());
    fp.surface_rms_dph = surface(lin.surface_columns, lin.surface_true_error, &fp.surface_bias_dph, &fp.surface_noise_dph);
    p.flights.push_back(fp);
  }
  if (envelope_->uniform_samples) {
    double bias = 0.0, noise = 0.0;
    p.uniform_surface_rms_dph = surface(lin_.uniform_columns, envelope_->uniform_true_error, &bias, &noise);
  }
  const auto effects = regressor_->effects();
  p.effect_correlation.resize(static_cast<Eigen::Index>(effects.size()), static_cast<Eigen::Index>(effects.size()));
  const Eigen::MatrixXd post = e.posterior_covariance();
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const auto [name, j] = effects[i];
    p.effects.push_back({name, std::sqrt(post(j, j)) * effect_unit(name).per_si, effect_unit(name).unit});
    for (std::size_t k = 0; k < effects.size(); ++k) {
      const Eigen::Index jk = effects[k].second;
      p.effect_correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = post(j, jk) / std::sqrt(post(j, j) * post(jk, jk));
    }
  }
  return p;
}

}  // namespace gyrosid::design
