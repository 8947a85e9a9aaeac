#include "noise/allan.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "core/error.h"
#include "core/nnls.h"
#include "core/stats.h"
#include "noise/processes.h"

namespace gyrosid {

std::string AllanOptions::validate() const {
  if (points_per_decade < 1 || points_per_decade > 100) return "points_per_decade must be in [1, 100]";
  if (!(max_tau_fraction > 0 && max_tau_fraction <= 0.5)) return "max_tau_fraction must be in (0, 0.5]";
  if (!(confidence > 0 && confidence < 1)) return "confidence must be in (0, 1)";
  return "";
}

double allan_edf(int alpha, double n, double m) {
  switch (alpha) {
    case 2:  // white PM
      return (n + 1) * (n - 2 * m) / (2 * (n - m));
    case 1: {  // flicker PM
      const double a = (n - 1) / (2 * m), b = (2 * m + 1) * (n - 1) / 4;
      return std::exp(std::sqrt(std::log(a) * std::log(b)));
    }
    case 0:  // white FM
      return (3 * (n - 1) / (2 * m) - 2 * (n - 2) / n) * (4 * m * m / (4 * m * m + 5));
    case -1:  // flicker FM
      return m == 1 ? 2 * (n - 2) * (n - 2) / (2.3 * n - 4.9) : 5 * n * n / (4 * m * (n + 3 * m));
    default: {  // random walk FM (also used for the steeper rate-ramp region)
      const double a = (n - 2) / (m * (n - 3) * (n - 3));
      return a * ((n - 1) * (n - 1) - 3 * m * (n - 1) + 4 * m * m);
    }
  }
}

AllanPhase::AllanPhase(std::span<const double> rate, double dt_s) : dt_(dt_s) {
  if (!(dt_s > 0)) fail("Allan deviation: sample interval ", dt_s, " s must be positive");
  const std::size_t n = rate.size();
  if (n < 4) fail("Allan deviation: need at least 4 samples, got ", n);
  // The second difference cancels a linear phase exactly; removing the mean rate keeps theta small so the
  // differences do not lose digits.
  long double mean = 0.0L;
  for (double r : rate) mean += r;
  mean /= static_cast<long double>(n);
  theta_.assign(n + 1, 0.0L);
  for (std::size_t k = 0; k < n; ++k) theta_[k + 1] = theta_[k] + (static_cast<long double>(rate[k]) - mean) * dt_s;
}

double AllanPhase::half_mean_square(std::size_t m) const {
  const std::size_t terms = theta_.size() - 2 * m;
  long double sum = 0.0L;
  for (std::size_t k = 0; k < terms; ++k) {
    const long double d = theta_[k + 2 * m] - 2.0L * theta_[k + m] + theta_[k];
    sum += d * d;
  }
  return static_cast<double>(sum / (2.0L * terms));
}

double AllanPhase::variance(std::size_t m) const {
  const double tau = static_cast<double>(m) * dt_;
  return half_mean_square(m) / (tau * tau);
}

double AllanPhase::robust_variance(std::size_t m) const {
  // Bisquare rho(u) = 1 - (1 - (u/c)^2)^3 for |u| < c, else 1; the scale s solves mean rho(d/s) = delta with
  // delta = E rho(Z) for a standard normal Z, so that s is the standard deviation of Gaussian d. Started from
  // the median absolute second difference, solved by the fixed point s^2 <- s^2 mean rho(d/s) / delta.
  constexpr double c = 3.0, delta = 0.242654076816;
  const std::size_t terms = theta_.size() - 2 * m;
  std::vector<double> d(terms);
  for (std::size_t k = 0; k < terms; ++k) d[k] = second_difference(k, m);
  std::vector<double> magnitude(terms);
  for (std::size_t k = 0; k < terms; ++k) magnitude[k] = std::abs(d[k]);
  const auto middle = magnitude.begin() + static_cast<std::ptrdiff_t>(terms / 2);
  std::nth_element(magnitude.begin(), middle, magnitude.end());
  double scale = *middle / 0.6744897501960817;
  if (!(scale > 0)) return variance(m);  // over half the differences are zero (a quantized, still signal)
  for (int iteration = 0; iteration < 100; ++iteration) {
    double mean_rho = 0.0;
    for (double x : d) {
      const double u = x / (c * scale);
      mean_rho += std::abs(u) < 1.0 ? 1.0 - std::pow(1.0 - u * u, 3) : 1.0;
    }
    mean_rho /= static_cast<double>(terms);
    const double next = scale * std::sqrt(mean_rho / delta);
    const bool converged = std::abs(next - scale) <= 1e-10 * scale;
    scale = next;
    if (converged) break;
  }
  const double tau = static_cast<double>(m) * dt_;
  return scale * scale / (2.0 * tau * tau);
}

std::vector<AllanPoint> overlapping_allan_deviation(const std::vector<double>& rate, double dt_s,
                                                    const AllanOptions& options) {
  if (const auto problem = options.validate(); !problem.empty()) fail("Allan deviation: ", problem);
  return overlapping_allan_deviation(AllanPhase(rate, dt_s), options);
}

std::vector<AllanPoint> overlapping_allan_deviation(const AllanPhase& phase, const AllanOptions& options) {
  if (const auto problem = options.validate(); !problem.empty()) fail("Allan deviation: ", problem);
  const std::size_t n = phase.samples();
  const double dt_s = phase.dt_s();
  const std::size_t max_m = std::max<std::size_t>(1, static_cast<std::size_t>(options.max_tau_fraction * n));
  std::vector<std::size_t> ms;
  for (int i = 0;; ++i) {
    const auto m = static_cast<std::size_t>(std::llround(std::pow(10.0, static_cast<double>(i) / options.points_per_decade)));
    if (m > max_m || 2 * m > n) break;
    if (ms.empty() || m != ms.back()) ms.push_back(m);
  }

  std::vector<AllanPoint> curve;
  for (std::size_t m : ms) {
    AllanPoint p;
    p.tau_s = static_cast<double>(m) * dt_s;
    p.terms = n + 1 - 2 * m;
    p.adev = options.robust ? std::sqrt(phase.robust_variance(m)) : std::sqrt(phase.half_mean_square(m)) / p.tau_s;
    curve.push_back(p);
  }

  // Noise identification from the local log-log slope mu of sigma^2 (sigma^2 ~ tau^mu), then edf and
  // chi-square interval.
  const double lo_p = 0.5 * (1.0 - options.confidence), hi_p = 1.0 - lo_p;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const std::size_t a = i >= 2 ? i - 2 : 0, b = std::min(curve.size() - 1, i + 2);
    double mu = -1.0;  // white FM when the slope cannot be estimated
    if (b > a && curve[a].adev > 0 && curve[b].adev > 0) {
      mu = 2.0 * std::log(curve[b].adev / curve[a].adev) / std::log(curve[b].tau_s / curve[a].tau_s);
    }
    const int mu_int = std::clamp(static_cast<int>(std::lround(mu)), -2, 1);
    curve[i].alpha = mu_int == -2 ? 2 : -mu_int - 1;  // mu=-1 -> 0 (WFM), 0 -> -1 (FFM), 1 -> -2 (RWFM)
    const double m = curve[i].tau_s / dt_s;
    double edf = allan_edf(curve[i].alpha, static_cast<double>(n + 1), m);
    // Conservative cap: no noise type but white PM exceeds about 1.5 n/m degrees of freedom, and a white-PM
    // identification at long tau (a noisy slope) must not claim n/2 of them.
    edf = std::clamp(edf, 1.0, std::min(static_cast<double>(curve[i].terms), 1.5 * static_cast<double>(n) / m + 2.0));
    if (options.robust) edf *= kRobustAllanEfficiency;  // the M-estimate spends some of the degrees of freedom
    curve[i].edf = edf;
    const double var = curve[i].adev * curve[i].adev;
    curve[i].ci_low = std::sqrt(var * edf / stats::chi2_quantile(hi_p, edf));
    curve[i].ci_high = std::sqrt(var * edf / stats::chi2_quantile(lo_p, edf));
  }
  return curve;
}

namespace {

// Fits sigma^2(tau_j) ~ sum_k a_k g_k(tau_j), a >= 0, by iteratively reweighted NNLS. An Allan variance
// estimate s_j is (model_j / edf_j) chi^2(edf_j): variance 2 model_j^2 / edf_j. Weighting each residual
// s_j - model_j by sqrt(edf_j / 2) / model_j (model from the previous pass; the data on the first) gives the
// quasi-likelihood (gamma GLM) estimate, which - unlike dividing by the data s_j - is not biased low by the
// noise in s_j.
Eigen::VectorXd fit_variance_terms(const std::vector<const AllanPoint*>& points,
                                   const std::function<Eigen::VectorXd(double tau)>& basis_at, double* cost) {
  const auto rows = static_cast<Eigen::Index>(points.size());
  const Eigen::Index cols = basis_at(points.front()->tau_s).size();
  Eigen::MatrixXd g(rows, cols);
  Eigen::VectorXd s(rows), model(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    g.row(i) = basis_at(points[i]->tau_s).transpose();
    s(i) = points[i]->adev * points[i]->adev;
    model(i) = s(i);
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(cols);
  for (int pass = 0; pass < 8; ++pass) {
    Eigen::MatrixXd a(rows, cols);
    Eigen::VectorXd b(rows);
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double w = std::sqrt(0.5 * points[i]->edf) / std::max(model(i), 1e-3 * s(i));
      a.row(i) = w * g.row(i);
      b(i) = w * s(i);
    }
    Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (scale(j) == 0) scale(j) = 1.0;
      a.col(j) /= scale(j);
    }
    const Eigen::VectorXd next = nnls(a, b).cwiseQuotient(scale);
    const bool converged = pass > 0 && (next - x).norm() <= 1e-10 * next.norm();
    x = next;
    model = g * x;
    if (converged) break;
  }
  if (cost) {
    // Gamma deviance: -log-likelihood of s_j ~ (model_j / edf_j) chi^2(edf_j) up to a constant; comparable
    // across models (the tau_c search of the Gauss-Markov fit).
    *cost = 0.0;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double ratio = s(i) / std::max(model(i), 1e-300);
      *cost += 0.5 * points[i]->edf * (ratio - std::log(ratio) - 1.0);
    }
  }
  return x;
}

std::vector<const AllanPoint*> usable(const std::vector<AllanPoint>& curve) {
  std::vector<const AllanPoint*> points;
  for (const auto& p : curve)
    if (p.adev > 0 && p.edf > 0) points.push_back(&p);
  return points;
}

double relative_rms(const std::vector<const AllanPoint*>& points, const std::function<double(double)>& model) {
  double ss = 0.0;
  for (const auto* p : points) {
    const double r = model(p->tau_s) / (p->adev * p->adev) - 1.0;
    ss += r * r;
  }
  return std::sqrt(ss / static_cast<double>(points.size()));
}

}  // namespace

GaussMarkovFit fit_gauss_markov(const std::vector<AllanPoint>& curve, bool with_white_noise, bool with_random_walk) {
  const auto points = usable(curve);
  if (points.size() < 3) fail("Gauss-Markov fit: need at least 3 Allan points, got ", points.size());
  // For a given tau_c the model is linear in (sigma^2, N^2): the weighted fit above; tau_c by a log-grid
  // search refined by golden section.
  auto solve = [&](double tau_c, GaussMarkovFit* out) {
    double cost = 0.0;
    const Eigen::VectorXd x = fit_variance_terms(points, [&](double tau) {
      Eigen::VectorXd v(1 + (with_white_noise ? 1 : 0) + (with_random_walk ? 1 : 0));
      v(0) = gauss_markov_allan_variance(1.0, tau_c, tau);
      if (with_white_noise) v(1) = 1.0 / tau;
      if (with_random_walk) v(v.size() - 1) = tau / 3.0;
      return v;
    }, &cost);
    if (out) {
      out->sigma = std::sqrt(std::max(0.0, x(0)));
      out->tau_s = tau_c;
      out->angle_random_walk = with_white_noise ? std::sqrt(std::max(0.0, x(1))) : 0.0;
      out->rate_random_walk = with_random_walk ? std::sqrt(std::max(0.0, x(x.size() - 1))) : 0.0;
    }
    return cost;
  };
  const double lo = std::log(points.front()->tau_s / 10.0), hi = std::log(points.back()->tau_s * 10.0);
  const int grid = 120;
  int best = 0;
  double best_cost = INFINITY;
  for (int i = 0; i <= grid; ++i) {
    const double c = solve(std::exp(lo + (hi - lo) * i / grid), nullptr);
    if (c < best_cost) {
      best_cost = c;
      best = i;
    }
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / grid, b = lo + (hi - lo) * std::min(grid, best + 1) / grid;
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double c1 = b - ratio * (b - a), c2 = a + ratio * (b - a);
  double f1 = solve(std::exp(c1), nullptr), f2 = solve(std::exp(c2), nullptr);
  for (int i = 0; i < 40; ++i) {
    if (f1 < f2) {
      b = c2, c2 = c1, f2 = f1, c1 = b - ratio * (b - a), f1 = solve(std::exp(c1), nullptr);
    } else {
      a = c1, c1 = c2, f1 = f2, c2 = a + ratio * (b - a), f2 = solve(std::exp(c2), nullptr);
    }
  }
  GaussMarkovFit fit;
  solve(std::exp(0.5 * (a + b)), &fit);
  fit.relative_rms_residual = relative_rms(points, [&](double tau) {
    return gauss_markov_allan_variance(fit.sigma, fit.tau_s, tau) + fit.angle_random_walk * fit.angle_random_walk / tau +
           fit.rate_random_walk * fit.rate_random_walk * tau / 3.0;
  });
  return fit;
}

}  // namespace gyrosid
