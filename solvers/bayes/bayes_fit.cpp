#include "solvers/bayes/bayes_fit.h"

#include <Eigen/Dense>
#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>

#include "core/bounded_search.h"
#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "core/units.h"
#include "model/fit_notes.h"
#include "model/gaussian_node.h"
#include "solvers/bayes/evidence.h"
#include "solvers/bayes/model_error.h"
#include "solvers/bayes/revisits.h"
#include "solvers/common/candidates.h"
#include "solvers/common/terminations.h"

namespace gyrosid {

void BayesFitOptions::bind(OptionTable& t) {
  t.integer("nodes", &nodes, 0, 5000, "dictionary size: centres at a farthest-point subset of the training inputs")
      .real("width", &width, 0.0, 1e3, "starting width when scan = 0 (normalised input units)", true)
      .real("min_width", &min_width, 0.0, 1e3, "lower bound of the widths", true)
      .real("max_width", &max_width, 0.0, 1e3, "upper bound of the widths", true)
      .flag("per_input_widths", &per_input_widths, "one width per input (else one for all)")
      .integer("scan", &scan, 0, 100, "common widths tried log-spaced over [scan_min, scan_max] before the gradient search (0: start at width)")
      .real("scan_min", &scan_min, 0.0, 1e3, "smallest width of the scan", true)
      .real("scan_max", &scan_max, 0.0, 1e3, "largest width of the scan", true)
      .integer("evaluations", &evaluations, 1, 10000, "evidence evaluations per gradient search")
      .text("algorithm", &algorithm, "NLopt algorithm of the width search: LD_LBFGS, LD_MMA, LD_SLSQP (gradient) or LN_BOBYQA, ...")
      .choice("noise", &noise, {"auto", "white", "coloured", "given"},
              "noise model: white; coloured (white + random walk + Gauss-Markov by Allan fit, Kalman-whitened); auto: coloured when the evidence says so; given: the given_* options")
      .integer("noise_passes", &noise_passes, 1, 10, "coloured: noise-model estimates, each from the previous fit's residual")
      .choice("drift_averaging", &drift_averaging, {"sigma", "mixture", "none"},
              "coloured: the fits along the slow drift term's ridge of equal evidence widen the covariance only (sigma), also move the mean (mixture), or are not made (none)")
      .choice("model_error", &model_error, {"cv", "none"},
              "cv: add to the predictive sigma the misfit variance that cross-validation over levels or time blocks reveals; none: the posterior alone")
      .integer("model_error_blocks", &model_error_blocks, 2, 1000, "model_error=cv: time blocks (folds) when no input is recorded at levels")
      .choice("model_error_groups", &model_error_groups, {"cells", "runs"},
              "model_error=cv: a fold's residuals averaged over cells of half a width per input (cells) or over runs of consecutive samples (runs)")
      .real("given_white_dph_at_1hz", &given_white_dph_at_1hz, 0.0, 1e6, "noise=given: white noise, deg/h at 1 Hz")
      .real("given_rrw_dph_rt_h", &given_rrw_dph_rt_h, 0.0, 1e6, "noise=given: rate random walk, deg/h/rt(h)")
      .real("given_gm_sigma_dph", &given_gm_sigma_dph, 0.0, 1e6, "noise=given: Gauss-Markov sigma, deg/h")
      .real("given_gm_tau_s", &given_gm_tau_s, 0.0, 1e9, "noise=given: Gauss-Markov correlation time, s");
}

std::string BayesFitOptions::validate() const {
  const nlopt_algorithm a = nlopt_algorithm_from_string(algorithm.c_str());
  if (static_cast<int>(a) < 0 || a >= NLOPT_NUM_ALGORITHMS) {
    return str_cat("option 'algorithm' = '", algorithm, "' is not an NLopt algorithm (e.g. LD_LBFGS, LN_BOBYQA)");
  }
  if (algorithm.size() < 2 || algorithm[0] == 'G') return str_cat("option 'algorithm' = '", algorithm, "': use a local algorithm (LD_* or LN_*)");
  if (!(min_width < max_width) || width < min_width || width > max_width) return "need min_width <= width <= max_width";
  if (noise == "given" && !(given_white_dph_at_1hz > 0)) return "noise=given needs given_white_dph_at_1hz > 0";
  if (noise == "given" && given_gm_sigma_dph > 0 && !(given_gm_tau_s > 0)) return "noise=given with a Gauss-Markov sigma needs given_gm_tau_s > 0";
  if (noise != "given" && (given_white_dph_at_1hz > 0 || given_rrw_dph_rt_h > 0 || given_gm_sigma_dph > 0)) {
    return "the given_* noise options need noise=given";
  }
  if (scan > 0 && !(scan_min <= scan_max && scan_min >= min_width && scan_max <= max_width)) {
    return "need min_width <= scan_min <= scan_max <= max_width";
  }
  return "";
}

NoiseModel scaled(NoiseModel m, double factor) {
  const double f2 = factor * factor;
  m.white_var *= f2, m.rw_q *= f2, m.gm_var *= f2;
  return m;
}

NoiseModel given_noise_model(const BayesFitOptions& o, double dt, double y_scale) {
  const double to_y = units::dph_to_radps(1.0) / y_scale;
  NoiseModel m;
  m.dt_s = dt;
  m.white_var = std::pow(o.given_white_dph_at_1hz * to_y, 2) / dt;  // sigma at 1 Hz -> per sample of dt seconds
  m.rw_q = std::pow(units::dph_rt_h_to_rad_s_rt_s(o.given_rrw_dph_rt_h) / y_scale, 2) * dt;
  m.gm_var = std::pow(o.given_gm_sigma_dph * to_y, 2);
  m.gm_tau_s = o.given_gm_tau_s;
  return m;
}

namespace {

// Sample times, their typical interval and the runs without gaps (for the Allan fit of the noise).
struct TimeAxis {
  std::vector<double> t_s;
  double dt_s = 1.0;
  std::vector<std::vector<Eigen::Index>> runs;
};

TimeAxis time_axis(const BayesProblem& p) {
  TimeAxis a;
  const Eigen::Index n = p.y.size();
  a.t_s = p.t_s;
  if (static_cast<Eigen::Index>(a.t_s.size()) != n) {
    a.t_s.resize(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) a.t_s[static_cast<std::size_t>(i)] = static_cast<double>(i);
  }
  a.dt_s = median_sample_interval(a.t_s);
  if (!(a.dt_s > 0)) fail("bayes: sample times must increase");
  a.runs.emplace_back();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i > 0 && a.t_s[static_cast<std::size_t>(i)] - a.t_s[static_cast<std::size_t>(i - 1)] > 1.5 * a.dt_s) a.runs.emplace_back();
    a.runs.back().push_back(i);
  }
  return a;
}

double optimise_precisions(RbfEvidence& ev, Precisions warm, bool fixed_beta) {
  if (!fixed_beta) return ev.optimise(warm);
  EvidenceBounds b;
  b.min_log_beta = b.max_log_beta = 0.0;  // known noise: Sigma_0 is the noise covariance itself
  return ev.optimise({warm.log_alpha, 0.0}, b);
}

}  // namespace

EvidenceAt evidence_at(const BayesProblem& p, const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths, const FixedPart& fixed,
                       bool fixed_beta, Precisions warm, Eigen::VectorXd* gradient) {
  const Eigen::MatrixXd phi = gaussian_columns(p.x, centres, widths);
  Eigen::MatrixXd phi_p = phi;
  fixed.project(phi_p);
  RbfEvidence ev(phi_p, fixed);
  EvidenceAt out{optimise_precisions(ev, warm, fixed_beta), ev.precisions()};
  if (gradient) {
    Eigen::MatrixXd g = ev.gradient_wrt_columns(phi_p, fixed.y_projected());
    if (fixed.whitener()) g = fixed.whitener()->apply_transpose(g, p.y.size());
    *gradient = log_width_gradient(g, phi, p.x, centres, widths);
  }
  return out;
}

InputLevels input_levels(const Eigen::VectorXd& v) {
  constexpr double kLevelGap = 0.01;  // normalised inputs span [-1, 1]
  InputLevels out;
  const Eigen::Index n = v.size();
  if (n < 2) return out;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return v(a) < v(b); });
  std::vector<double> gaps;
  double covered = 0.0;
  std::vector<int> level(static_cast<std::size_t>(n), 0);
  int current = 0;
  for (std::size_t i = 1; i < order.size(); ++i) {
    const double gap = v(order[i]) - v(order[i - 1]);
    if (gap > kLevelGap) gaps.push_back(gap), covered += gap, ++current;
    level[static_cast<std::size_t>(order[i])] = current;
  }
  if (!(covered > 0.5 * (v(order.back()) - v(order.front())))) return out;
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  out.level = std::move(level), out.spacing = gaps[gaps.size() / 2], out.count = current + 1;
  return out;
}

// The narrowest identifiable width of each input: an input recorded at discrete levels (a rate table's
// plateaus, a chamber's temperature steps; input_levels) carries no information between its levels, where a
// narrower node would fall back to the prior mean and its predictive sigma would vanish with the node; the
// evidence cannot see this. Its bound is the median spacing of the levels; other inputs keep min_width.
std::vector<double> identifiable_min_widths(const Eigen::MatrixXd& x, double min_width) {
  std::vector<double> bounds;
  for (Eigen::Index k = 0; k < x.cols(); ++k) bounds.push_back(std::max(min_width, input_levels(x.col(k)).spacing));
  return bounds;
}

namespace {

// The evidence as a function of the log widths, for one noise model (one FixedPart); keeps the best point.
class WidthSearch {
 public:
  WidthSearch(const BayesProblem& p, const Eigen::MatrixXd& centres, const FixedPart& fixed, bool fixed_beta,
              SolveMonitor& monitor)
      : p_(p), centres_(centres), fixed_(fixed), fixed_beta_(fixed_beta), monitor_(monitor) {}

  // -log evidence / N at log widths rho (one per input, or one for all); fills the gradient if asked.
  double operator()(const std::vector<double>& rho, std::vector<double>& gradient) {
    Eigen::VectorXd g;
    const EvidenceAt at = evidence_at(p_, centres_, widths_of(rho), fixed_, fixed_beta_, warm_, gradient.empty() ? nullptr : &g);
    ++evaluations_;
    const double n = static_cast<double>(p_.y.size());
    monitor_.iteration(-at.value / n);
    if (at.value > best_value_) best_value_ = at.value, best_rho_ = rho, best_ = at.precisions;
    if (gradient.size() == 1) gradient[0] = -g.sum() / n;
    else
      for (std::size_t k = 0; k < gradient.size(); ++k) gradient[k] = -g(static_cast<Eigen::Index>(k)) / n;
    return -at.value / n;
  }

  Eigen::RowVectorXd widths_of(const std::vector<double>& rho) const {
    const Eigen::Index d = p_.x.cols();
    Eigen::RowVectorXd w(d);
    for (Eigen::Index k = 0; k < d; ++k) w(k) = std::exp(rho[rho.size() == 1 ? 0 : static_cast<std::size_t>(k)]);
    return w;
  }

  void warm_start(const Precisions& p) { warm_ = p; }
  const std::vector<double>& best_rho() const { return best_rho_; }
  double best_value() const { return best_value_; }
  const Precisions& best_precisions() const { return best_; }
  int evaluations() const { return evaluations_; }

 private:
  const BayesProblem& p_;
  const Eigen::MatrixXd& centres_;
  const FixedPart& fixed_;
  bool fixed_beta_;
  SolveMonitor& monitor_;
  Precisions warm_{0.0, std::log(10.0)}, best_;
  std::vector<double> best_rho_;
  double best_value_ = -INFINITY;
  int evaluations_ = 0;
};

struct SearchOutcome {
  Eigen::RowVectorXd widths;
  Precisions precisions;
  Termination termination = Termination::converged;
  std::string message;
};

// Scan of one common width (unless a start is given), then the bounded search over the log widths, each
// bounded below by `min_widths` (identifiable_min_widths).
SearchOutcome search_widths(WidthSearch& search, const BayesFitOptions& o, const std::vector<double>& min_widths, const std::vector<double>* start) {
  const std::size_t nv = o.per_input_widths ? min_widths.size() : 1;
  std::vector<double> lower(nv, std::log(*std::max_element(min_widths.begin(), min_widths.end())));
  if (o.per_input_widths) std::transform(min_widths.begin(), min_widths.end(), lower.begin(), [](double w) { return std::log(w); });
  const std::vector<double> upper(nv, std::log(std::max(o.max_width, std::exp(*std::max_element(lower.begin(), lower.end())))));
  auto bounded = [&](std::vector<double> rho) {
    if (rho.size() != nv) rho.assign(nv, rho[0]);
    for (std::size_t k = 0; k < nv; ++k) rho[k] = std::clamp(rho[k], lower[k], upper[k]);
    return rho;
  };
  std::vector<double> rho;
  std::vector<double> none;
  double best = INFINITY;
  if (start) best = search(rho = bounded(*start), none);
  // The scan runs even from a warm start: a warm start from the white fit is where its surface bent to follow
  // drift (a narrow temperature width), which a coloured noise model explains with far higher evidence.
  std::vector<double> scanned;            // log widths of the scan
  std::set<std::vector<double>> tried;    // the (bounded) points evaluated
  for (int i = 0; i < o.scan; ++i) {
    const double f = o.scan == 1 ? 0.5 : static_cast<double>(i) / (o.scan - 1);
    scanned.push_back(std::log(o.scan_min) + f * (std::log(o.scan_max) - std::log(o.scan_min)));
    const std::vector<double> r = bounded({scanned.back()});
    tried.insert(r);
    const double v = search(r, none);
    if (v < best) best = v, rho = r;
  }
  // A network the data support only with unequal widths: where every common width leaves it off (alpha at
  // its bound, the evidence flat in the widths, so the gradient search cannot leave the plateau), the scan's
  // widths are tried per input on a grid (two inputs). The hybrid on the 8-h classical soak, seed 1 (13
  // temperature plateaus): every common width off, log evidence 8390.97; temperature 0.2 and rate 1.5 give
  // 8397.53 with 7.3 effective parameters, and the soak's criterion of fit over 30 seeds was 0.126 m (short
  // flight) where the network stayed off against 0.069 m where it did not (trajectory_design/README.md).
  if (nv == 2 && !scanned.empty() && search.best_precisions().log_alpha >= EvidenceBounds{}.max_log_alpha - 1e-9) {
    for (double a : scanned)
      for (double b : scanned) {
        const std::vector<double> r = bounded({a, b});
        if (!tried.insert(r).second) continue;  // the same point after the bounds
        const double v = search(r, none);
        if (v < best) best = v, rho = r;
      }
  }
  if (rho.empty()) rho = bounded({std::log(o.width)});
  search.warm_start(search.best_precisions());
  BoundedSearchOptions so;
  so.algorithm = o.algorithm, so.max_evaluations = o.evaluations, so.xtol_rel = 1e-3;
  const BoundedSearchResult r = minimize_bounded(ObjectiveWithGradient(std::ref(search)), rho, lower, upper, so);
  SearchOutcome out;
  out.widths = search.widths_of(search.best_rho());
  out.precisions = search.best_precisions();
  out.termination = r.threw ? Termination::no_progress : termination_of(r.result);
  out.message = r.message;
  return out;
}

// Weights, covariance and residual at the chosen widths and precisions.
void finish(const BayesProblem& p, const FixedPart& fixed, const SearchOutcome& s, bool fixed_beta, BayesFit& fit) {
  fit.widths = s.widths;
  const Eigen::MatrixXd phi = gaussian_columns(p.x, fit.centres, s.widths);
  Eigen::MatrixXd phi_w = fixed.whitener() ? fixed.whitener()->apply(phi) : phi;
  const Eigen::MatrixXd c = fixed.q().transpose() * phi_w;  // P x M
  Eigen::MatrixXd& phi_p = phi_w;
  if (fixed.columns() > 0) phi_p -= fixed.q() * c;
  RbfEvidence ev(phi_p, fixed);
  fit.log_evidence = optimise_precisions(ev, s.precisions, fixed_beta);
  fit.log_alpha = ev.precisions().log_alpha, fit.log_beta = ev.precisions().log_beta, fit.gamma = ev.gamma();
  const double beta = std::exp(fit.log_beta);
  fit.rbf_weights = ev.mean();
  const Eigen::MatrixXd cov_w = ev.covariance();
  // Fixed weights given the RBF weights: v = R_F^-1 (Q_F' W y - C w), with covariance R_F^-1 R_F^-T / beta
  // from the noise; jointly (flat prior on v) the covariance below.
  const Eigen::Index m = fit.rbf_weights.size(), q = fixed.columns();
  const auto r = fixed.r().triangularView<Eigen::Upper>();
  const Eigen::MatrixXd rinv = r.solve(Eigen::MatrixXd::Identity(q, q));
  fit.covariance.resize(m + q, m + q);
  if (m == 0) {  // no RBF part: generalised least squares (Eigen's solvers are not for zero-column blocks)
    fit.fixed_weights = r.solve(fixed.qy());
    fit.covariance = rinv * rinv.transpose() / beta;
    return;
  }
  fit.fixed_weights = r.solve(fixed.qy() - c * fit.rbf_weights);
  const Eigen::MatrixXd k = r.solve(c);  // P x M
  fit.covariance.topLeftCorner(m, m) = cov_w;
  fit.covariance.bottomLeftCorner(q, m) = -k * cov_w;
  fit.covariance.topRightCorner(m, q) = fit.covariance.bottomLeftCorner(q, m).transpose();
  fit.covariance.bottomRightCorner(q, q) = k * cov_w * k.transpose() + rinv * rinv.transpose() / beta;
}

Eigen::VectorXd residual(const BayesProblem& p, const BayesFit& fit) {
  Eigen::VectorXd r = p.y - p.fixed * fit.fixed_weights;
  if (fit.rbf_weights.size() > 0) r -= gaussian_columns(p.x, fit.centres, fit.widths) * fit.rbf_weights;
  return r;
}

// One complete fit under one noise model (nullptr: white), starting the search at `start` if given.
BayesFit fit_under(const BayesProblem& p, const BayesFitOptions& o, const Whitener* whitener, bool fixed_beta,
                   const std::vector<double>* start, const Eigen::MatrixXd& centres, SolveMonitor& monitor) {
  const FixedPart fixed(p.fixed, p.y, whitener);
  BayesFit fit;
  fit.centres = centres;
  WidthSearch search(p, centres, fixed, fixed_beta, monitor);
  SearchOutcome s;
  if (centres.rows() == 0) {
    s.widths = Eigen::RowVectorXd::Ones(p.x.cols());
  } else {
    s = search_widths(search, o, identifiable_min_widths(p.x, o.min_width), start);
  }
  finish(p, fixed, s, fixed_beta, fit);
  fit.termination = s.termination, fit.message = s.message, fit.evaluations = search.evaluations();
  return fit;
}

std::vector<double> log_widths(const BayesFit& fit, bool per_input) {
  std::vector<double> rho;
  for (Eigen::Index k = 0; k < (per_input ? fit.widths.size() : 1); ++k) rho.push_back(std::log(fit.widths(k)));
  return rho;
}

// The noise model's free parameters for a search: logs of the white variance, the random-walk increment
// variance, the Gauss-Markov variance and time, bounded; a term at its lower bound is dropped. Without
// `random_walk` the family is white + Gauss-Markov (the random walk held at zero, not searched).
struct NoiseParameters {
  std::vector<double> lower, upper, start;  // full layout: white, random walk, Gauss-Markov variance, tau
  double dt_s;
  bool random_walk = true;

  NoiseParameters(const TimeAxis& axis, const NoiseModel& from, bool with_random_walk = true) : dt_s(axis.dt_s), random_walk(with_random_walk) {
    const double span = std::max(axis.t_s.back() - axis.t_s.front(), 10 * axis.dt_s);
    const double w0 = std::max(from.white_var, 1e-10);
    lower = {std::log(1e-12), std::log(1e-9 * w0 * axis.dt_s / span), std::log(1e-6 * w0), std::log(2 * axis.dt_s)};
    upper = {std::log(10.0), std::log(10.0 * axis.dt_s / span), std::log(10.0), std::log(2 * span)};
    start = {std::log(w0), std::log(std::max(from.rw_q, 0.01 * w0 * axis.dt_s / span)), std::log(std::max(from.gm_var, 0.01 * w0)),
             std::log(from.gm_var > 0 ? from.gm_tau_s : 0.1 * span)};
    for (std::size_t k = 0; k < start.size(); ++k) start[k] = std::clamp(start[k], lower[k], upper[k]);
    if (!random_walk) start[1] = lower[1];
  }
  // The searched coordinates (the random walk's left out of the white + Gauss-Markov family).
  std::vector<double> searched(const std::vector<double>& full) const {
    if (random_walk) return full;
    return {full[0], full[2], full[3]};
  }
  std::vector<double> full(const std::vector<double>& v) const {
    if (random_walk) return v;
    return {v[0], lower[1], v[1], v[2]};
  }
  NoiseModel model(const std::vector<double>& searched_v) const {
    const std::vector<double> v = full(searched_v);
    NoiseModel m;
    m.dt_s = dt_s;
    m.white_var = std::exp(v[0]);
    m.rw_q = v[1] <= lower[1] + 1e-6 ? 0.0 : std::exp(v[1]);
    m.gm_var = v[2] <= lower[2] + 1e-6 ? 0.0 : std::exp(v[2]);
    m.gm_tau_s = m.gm_var > 0 ? std::exp(v[3]) : 0.0;
    return m;
  }
  struct Optimum {
    NoiseModel model;
    double value;  // the objective's minimum
  };
  Optimum minimise(const std::function<double(const std::vector<double>&)>& objective, int evaluations) const {
    BoundedSearchOptions so;
    so.algorithm = "LN_BOBYQA", so.max_evaluations = evaluations, so.xtol_rel = 1e-3;
    const BoundedSearchResult r = minimize_bounded(objective, searched(start), searched(lower), searched(upper), so);
    return {model(r.x), r.value};
  }
};

// Gaussian log-likelihood of a residual r under a noise model: -1/2 (|W r|^2 + log|Sigma| + N log 2 pi).
double residual_log_likelihood(const Eigen::VectorXd& r, const NoiseModel& m, const TimeAxis& axis, const std::vector<Eigen::Index>& rows) {
  const Whitener w(m, rows, axis.t_s, RandomWalkStart::zero);
  return -0.5 * (w.apply(r).squaredNorm() + w.log_determinant() + static_cast<double>(r.size()) * kLog2Pi);
}

// Maximum likelihood of the noise model for a fixed residual (the plug-in estimate: O(N) per evaluation, a
// screen for drift before any refit; the fit that produced r has absorbed some of it).
NoiseModel noise_of_residual(const Eigen::VectorXd& r, const TimeAxis& axis, const std::vector<Eigen::Index>& rows,
                             const NoiseModel& start, SolveMonitor& monitor) {
  const NoiseParameters np(axis, start);
  return np.minimise([&](const std::vector<double>& v) {
    const double value = -residual_log_likelihood(r, np.model(v), axis, rows);
    monitor.iteration(value / static_cast<double>(r.size()));
    return value;
  }, 80).model;
}

// The log evidence of the problem under one noise model at fixed widths (phi: the unwhitened columns), with
// beta = 1 (Sigma_0 is the noise covariance itself) and the RBF weights and fixed columns integrated out.
double evidence_under(const BayesProblem& p, const Eigen::MatrixXd& phi, const NoiseModel& model, const TimeAxis& axis,
                      const std::vector<Eigen::Index>& rows, const Precisions& warm) {
  const Whitener w(model, rows, axis.t_s, RandomWalkStart::zero);
  const FixedPart fixed(p.fixed, p.y, &w);
  Eigen::MatrixXd phi_p = phi;
  fixed.project(phi_p);
  RbfEvidence ev(phi_p, fixed);
  return optimise_precisions(ev, warm, true);
}

// Type-II maximum likelihood of the noise model at fixed widths (evidence_under), by a local search from
// `start` - what the plug-in estimate of the residual misses - in the white + random walk + Gauss-Markov
// family (random_walk) or white + Gauss-Markov.
struct NoiseByEvidence {
  NoiseModel model;
  double log_evidence;
  std::string family;  // nested_noise_by_evidence: which family was kept, and the evidence that decided it
};
NoiseByEvidence noise_by_evidence(const BayesProblem& p, const Eigen::MatrixXd& phi, const TimeAxis& axis, const std::vector<Eigen::Index>& rows,
                                  const NoiseModel& start, bool random_walk, const Precisions& warm, SolveMonitor& monitor) {
  const NoiseParameters np(axis, start, random_walk);
  const NoiseParameters::Optimum o = np.minimise([&](const std::vector<double>& x) {
    const double value = evidence_under(p, phi, np.model(x), axis, rows, warm);
    monitor.iteration(-value / static_cast<double>(p.y.size()));
    return -value;
  }, 60);
  return {o.model, -o.value, ""};
}

// The noise model by the evidence, a random walk admitted only where it earns its parameter. A Gauss-Markov
// wander is a random walk at frequencies above 1/(2 pi tau) (spectrum 2 sigma^2 / (tau w^2) against q / w^2,
// so q = 2 sigma^2 / tau): once tau nears the record's span the two differ only at periods the record does
// not hold, the evidence has a ridge, and a local search lands anywhere on it. The hybrid on a dual scan of
// experiments/trajectory_design/other_fog.yaml without its coil lag (white 4 deg/h at 1 Hz, GM 3 deg/h at
// 600 s, 0.5 deg/h/rt(h)), log evidence with the noise given and the widths fitted: 9085.9 at the truth,
// 9085.5 for a 10.4 deg/h/rt(h) walk alone, 9085.6 for the 9.6 deg/h/rt(h) walk with a 1.1 deg/h, 332-s
// wander the search had chosen (experiments/noisy_calibration, "Fourth run"). They are not equal for the
// calibration: a walk has no level, so the fit discards the slow information the bias needs (criterion of
// fit on the short flight 0.35 m against 0.035 m under the truth). A random walk is a
// Gauss-Markov process with tau beyond the search's bound (2 spans), so the family white + Gauss-Markov
// covers it on the record; the walk is added when the nested model white + random walk + Gauss-Markov
// raises the evidence by more than BIC's penalty for its one parameter, 1/2 ln N. Both are searched, the
// white + Gauss-Markov family from `start`'s Gauss-Markov term, or one of a tenth of the span as large as
// the white noise (explain's start for a slow wander, explain/noise_likelihood.cpp), and from the full
// search's walk turned into a wander of a tenth of the span on its ridge.
NoiseByEvidence nested_noise_by_evidence(const BayesProblem& p, const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths, const TimeAxis& axis,
                                         const std::vector<Eigen::Index>& rows, const NoiseModel& start, const Precisions& warm, SolveMonitor& monitor) {
  const Eigen::MatrixXd phi = gaussian_columns(p.x, centres, widths);
  const NoiseByEvidence full = noise_by_evidence(p, phi, axis, rows, start, true, warm, monitor);
  const double span = std::max(axis.t_s.back() - axis.t_s.front(), 10 * axis.dt_s);
  NoiseModel wander = start;
  if (!(wander.gm_var > 0)) {
    wander.gm_var = wander.white_var, wander.gm_tau_s = 0.1 * span;
  }
  NoiseByEvidence stationary = noise_by_evidence(p, phi, axis, rows, wander, false, warm, monitor);
  if (full.model.rw_q > 0) {
    // Also from the walk the full search found, as the wander of the same intensity (q = 2 sigma^2 dt / tau,
    // the same spectrum above 1/(2 pi tau)) at a tenth of the span: a start on the ridge the walk lies on.
    NoiseModel ridge = full.model;
    ridge.gm_tau_s = 0.1 * span, ridge.gm_var = full.model.rw_q * ridge.gm_tau_s / (2 * axis.dt_s), ridge.rw_q = 0.0;
    const NoiseByEvidence other = noise_by_evidence(p, phi, axis, rows, ridge, false, warm, monitor);
    if (other.log_evidence > stationary.log_evidence) stationary = other;
  }
  const double penalty = 0.5 * std::log(static_cast<double>(p.y.size()));
  const double gain = full.log_evidence - stationary.log_evidence;
  // (a full search that dropped the walk is a second start of the white + Gauss-Markov family: the better wins)
  NoiseByEvidence out = gain > (full.model.rw_q > 0 ? penalty : 0.0) ? full : stationary;
  out.family = str_cat(out.model.rw_q > 0 ? "random walk kept" : "no random walk", ": with it the log evidence ",
                       gain >= 0 ? "+" : "", format_significant(gain, 3), " over a Gauss-Markov wander alone (BIC's penalty ",
                       format_significant(penalty, 3), ")");
  return out;
}

// Noise search and width search in turn, `noise_passes` times, from the white fit and the noise model `model`.
BayesFit coloured_passes(const BayesProblem& p, const BayesFitOptions& o, const Eigen::MatrixXd& centres, const TimeAxis& axis,
                         const std::vector<Eigen::Index>& rows, const BayesFit& white, NoiseModel model, SolveMonitor& monitor) {
  BayesFit current = white;
  Precisions warm{white.log_alpha, 0.0};
  for (int pass = 0; pass < o.noise_passes; ++pass) {
    const NoiseByEvidence chosen = nested_noise_by_evidence(p, centres, current.widths, axis, rows, model, warm, monitor);
    model = chosen.model;
    const Whitener w(model, rows, axis.t_s, RandomWalkStart::zero);
    const std::vector<double> start = log_widths(current, o.per_input_widths);
    BayesFit fit = fit_under(p, o, &w, true, &start, centres, monitor);
    fit.evaluations += current.evaluations;
    fit.noise = model;
    fit.noise_sigma = std::sqrt(model.white_var);
    fit.noise_family = chosen.family;
    warm = {fit.log_alpha, 0.0};
    current = fit;
  }
  return current;
}

// Bayesian averaging over the scale of the slow noise term (the predictive sigma must carry the uncertainty
// of a drift whose tau is comparable to the record). Along the ridge of equal drift intensity (gm_var / tau
// fixed: the same spectrum above 1/tau, so the short lags agree) the evidence is nearly flat once tau nears
// the record's span: 62 min of Gauss-Markov 10 deg/h, tau 1000 s (the reference sensor) is fitted as 6.3
// deg/h, 415 s at equal evidence, and the sigma of that one point covers 68 % of the held-out errors. Points
// tau* x {1/4, 1/2, 1, 2, 4} on the ridge (inside the search's bounds [2 dt, 2 span]), uniform prior in log
// tau, weights w_i = exp(log evidence_i - max) normalised; the fit carries the mixture's two moments:
//   theta = sum w_i theta_i,   P = sum w_i (P_i + d_i d_i'),   d_i = theta_i - theta   (theta = [rbf, fixed]).
// move_mean false (drift_averaging=sigma): theta stays the fit's, P the mixture's second moment about it.
void average_slow_drift(const BayesProblem& p, BayesFit& fit, bool move_mean, const std::vector<Eigen::Index>& rows, const TimeAxis& axis,
                        SolveMonitor& monitor) {
  if (!fit.noise || !(fit.noise->gm_var > 0)) return;
  const NoiseModel base = *fit.noise;
  const double span = std::max(axis.t_s.back() - axis.t_s.front(), 10 * axis.dt_s);
  std::vector<BayesFit> points;
  std::vector<double> factors;
  for (const double f : {0.25, 0.5, 1.0, 2.0, 4.0}) {
    const double tau = base.gm_tau_s * f;
    if (f != 1.0 && (tau < 2 * axis.dt_s || tau > 2 * span)) continue;
    if (f == 1.0) {
      points.push_back(fit), factors.push_back(f);
      continue;
    }
    NoiseModel m = base;
    m.gm_tau_s = tau, m.gm_var = base.gm_var * f;
    const Whitener w(m, rows, axis.t_s, RandomWalkStart::zero);
    const FixedPart fixed(p.fixed, p.y, &w);
    SearchOutcome s;
    s.widths = fit.widths, s.precisions = {fit.log_alpha, 0.0};
    BayesFit point;
    point.centres = fit.centres;
    finish(p, fixed, s, true, point);
    monitor.iteration(-point.log_evidence / static_cast<double>(p.y.size()));
    points.push_back(point), factors.push_back(f);
  }
  double top = -INFINITY;
  for (const auto& q : points) top = std::max(top, q.log_evidence);
  const Eigen::Index m = fit.rbf_weights.size(), q = fit.fixed_weights.size();
  std::vector<double> w;
  std::vector<Eigen::VectorXd> theta;
  double total = 0.0;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(m + q);
  for (const auto& point : points) {
    w.push_back(std::exp(point.log_evidence - top)), total += w.back();
    theta.emplace_back(m + q);
    theta.back() << point.rbf_weights, point.fixed_weights;
  }
  for (std::size_t i = 0; i < points.size(); ++i) mean += (w[i] /= total) * theta[i];
  if (!move_mean) mean << fit.rbf_weights, fit.fixed_weights;
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(m + q, m + q);
  std::ostringstream note;
  note << "averaged over the Gauss-Markov term's tau along its ridge of equal drift intensity: weights";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::VectorXd d = theta[i] - mean;
    cov += w[i] * (points[i].covariance + d * d.transpose());
    note << " " << format_significant(w[i], 2) << " (tau x" << factors[i] << ")";
  }
  fit.rbf_weights = mean.head(m), fit.fixed_weights = mean.tail(q), fit.covariance = cov;
  fit.noise_averaging = note.str();
}

std::string describe(const NoiseModel& m, double to_dph) {
  std::ostringstream s;
  s << "white " << format_significant(std::sqrt(m.white_var) * to_dph, 3) << " deg/h per sample";
  if (m.rw_q > 0) s << ", random walk " << format_significant(std::sqrt(m.rw_q / m.dt_s) * to_dph * 60.0, 3) << " deg/h/rt(h)";
  if (m.gm_var > 0) s << ", Gauss-Markov " << format_significant(std::sqrt(m.gm_var) * to_dph, 3) << " deg/h, tau " << format_significant(m.gm_tau_s, 3) << " s";
  return s.str();
}

}  // namespace

nlohmann::json BayesFit::details(double y_scale) const {
  nlohmann::json j = {{"width", std::vector<double>(widths.data(), widths.data() + widths.size())},
                      {"alpha", std::exp(log_alpha)}, {"beta", std::exp(log_beta)},
                      {"effective_parameters", gamma}, {"log_evidence", log_evidence},
                      {"noise_sigma_radps", noise_sigma * y_scale}, {"evaluations", evaluations}};
  FitNotes notes;
  notes.noise_choice = noise_choice;
  notes.noise_identification = noise_identification;
  write_fit_notes(notes, j);
  if (!noise_averaging.empty()) j["noise_averaging"] = noise_averaging;
  if (!model_error_note.empty()) {
    const double to_dph2 = std::pow(y_scale * 180.0 / 3.14159265358979323846 * 3600.0, 2);
    j["model_error"] = model_error_note;
    j["model_error_figures_dph2"] = {{"added", model_error_var * to_dph2}, {"excess", model_error_excess * to_dph2},
                                     {"standard_error", model_error_standard_error * to_dph2}, {"reach", model_error_reach}};
    j["cv_rms_dph"] = std::sqrt(cv_mse * to_dph2);
  }
  if (noise) j["noise_model_dph"] = scaled(*noise, y_scale * 180.0 / 3.14159265358979323846 * 3600.0).to_json();
  return j;
}

namespace {

// noise=auto keeps white noise when at least kMinRevisits revisits differ by under kMisfitRatio of what
// samples as far apart in time differ by (revisits.h; with 30 pairs the ratio's standard error under real
// drift is ~0.26).
constexpr int kMinRevisits = 30;
constexpr double kMisfitRatio = 0.25;

// Widths, prior and noise (fit_bayes without the model-error estimate).
BayesFit fit_widths_and_noise(const BayesProblem& p, const BayesFitOptions& o, SolveMonitor& monitor) {
  if (p.x.rows() != p.y.size() || p.fixed.rows() != p.y.size()) fail("bayes: inputs, target and fixed columns differ in length");
  const Eigen::MatrixXd centres = o.nodes > 0 ? rows_of(p.x, select_candidates(p.x, o.nodes)) : Eigen::MatrixXd(0, p.x.cols());
  const TimeAxis axis = time_axis(p);
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(p.y.size()));
  for (Eigen::Index i = 0; i < p.y.size(); ++i) rows[static_cast<std::size_t>(i)] = i;
  if (p.given_noise) {  // known noise: one fit, beta = 1
    const Whitener w(*p.given_noise, rows, axis.t_s, RandomWalkStart::zero);
    BayesFit fit = fit_under(p, o, &w, true, nullptr, centres, monitor);
    fit.noise = *p.given_noise;
    fit.noise_sigma = std::sqrt(p.given_noise->white_var);
    fit.noise_choice = "given: " + describe(*p.given_noise, p.report_scale);
    return fit;
  }
  BayesFit white = fit_under(p, o, nullptr, false, nullptr, centres, monitor);
  white.noise_sigma = std::exp(-0.5 * white.log_beta);
  white.noise_choice = "white (option noise=white)";
  if (o.noise == "white") return white;

  // Screen: the white fit's residual under the best coloured model against white noise (plug-in likelihoods).
  const Eigen::VectorXd r = residual(p, white);
  NoiseModel white_only;
  white_only.dt_s = axis.dt_s, white_only.white_var = r.squaredNorm() / static_cast<double>(r.size());
  NoiseIdentification identified;
  const NoiseModel allan = fit_noise_model(r, axis.runs, axis.dt_s, NoiseStart::identified, &identified);
  // The one noise estimator's reading of the white fit's residual (noise/identify.h), in deg/h: what `gyrosid
  // allan` would say of it; the whitening below is its projection refined by likelihood.
  white.noise_identification =
      identified.samples > 0 ? str_cat(identified.structure.name(), ": ", identified.model.scaled(p.report_scale).describe("deg/h"), ", from ",
                                       format_significant(identified.fit_tau_low_s, 3), " to ", format_significant(identified.fit_tau_high_s, 3), " s")
                             : "";
  const NoiseModel screened = noise_of_residual(r, axis, rows, allan, monitor);
  const double screen = residual_log_likelihood(r, screened, axis, rows) - residual_log_likelihood(r, white_only, axis, rows);
  const double screen_penalty = 0.5 * std::max(1, screened.parameters() - 1) * std::log(static_cast<double>(p.y.size()));
  std::optional<BayesFit> coloured;
  const bool drift = screened.rw_q > 0 || screened.gm_var > 0;
  std::string revisits;
  if (drift && o.noise == "auto" && screen > screen_penalty) {
    // The time correlation may be the misfit of the model class, not drift: revisits tell (revisits.h).
    const RevisitCheck check = check_revisits(p.x, white.widths, r, axis.t_s, screened);
    revisits = str_cat("; ", check.describe());
    if (check.pairs >= kMinRevisits && check.ratio() < kMisfitRatio) {
      white.noise_choice = str_cat("white: the residual is correlated in time (", describe(screened, p.report_scale), " raises its likelihood by ",
                                   format_significant(screen, 3), "), but ", check.describe(), ", below ", kMisfitRatio,
                                   ": the correlation is the model's misfit (a function of the inputs), not drift");
      return white;
    }
  }
  if (drift && (o.noise == "coloured" || screen > screen_penalty)) {
    // The evidence search starts from the Allan fit: the plug-in estimate lets a random walk stand in for
    // drift the white fit has half absorbed.
    coloured = coloured_passes(p, o, centres, axis, rows, white, allan, monitor);
    coloured->noise_identification = white.noise_identification;
    if (o.drift_averaging != "none") average_slow_drift(p, *coloured, o.drift_averaging == "mixture", rows, axis, monitor);
  } else if (o.noise == "auto") {
    white.noise_choice = str_cat("white: the best coloured model of the residual (", describe(screened, p.report_scale), ") raises its likelihood by ",
                                 format_significant(screen, 3), ", below BIC's penalty ", format_significant(screen_penalty, 3));
    return white;
  }
  if (!coloured) {
    white.noise_choice = "white: no random walk or Gauss-Markov drift in the residual";
    return white;
  }
  const int extra = std::max(1, coloured->noise->parameters() - 1);
  const double penalty = 0.5 * extra * std::log(static_cast<double>(p.y.size()));
  const double gain = coloured->log_evidence - white.log_evidence;
  const std::string coloured_model = describe(*coloured->noise, p.report_scale);
  if (o.noise == "coloured" || gain > penalty) {
    coloured->noise_choice = str_cat("coloured (", coloured_model, "): log evidence +", format_significant(gain, 3),
                                     " over white noise, above BIC's penalty ", format_significant(penalty, 3), " for the drift parameters",
                                     coloured->noise_family.empty() ? "" : "; " + coloured->noise_family, revisits);
    return *coloured;
  }
  white.noise_choice = str_cat("white: the coloured model (", coloured_model, ") gains ", format_significant(gain, 3),
                               " in log evidence, below BIC's penalty ", format_significant(penalty, 3));
  white.evaluations = coloured->evaluations;
  return white;
}

}  // namespace

BayesFit fit_bayes(const BayesProblem& p, const BayesFitOptions& o, SolveMonitor& monitor) {
  BayesFit fit = fit_widths_and_noise(p, o, monitor);
  // A given noise model stands for the truth (the Cramer-Rao floor): its posterior is left as it is.
  if (o.model_error == "cv" && !p.given_noise) {
    ModelErrorOptions mo;
    mo.blocks = o.model_error_blocks;
    mo.groups = o.model_error_groups == "runs" ? ModelErrorGroups::runs : ModelErrorGroups::cells;
    const ModelErrorEstimate e = model_error_by_cv(p, fit, time_axis(p).t_s, mo);
    fit.model_error_var = e.variance;
    fit.model_error_excess = e.mean_excess, fit.model_error_standard_error = e.standard_error, fit.model_error_reach = e.reach;
    fit.cv_mse = e.cv_mse;
    fit.model_error_note = e.describe(p.report_scale);
  }
  return fit;
}

}  // namespace gyrosid
