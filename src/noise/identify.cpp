#include "noise/identify.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "core/bounded_search.h"
#include "core/error.h"
#include "core/format.h"
#include "core/nnls.h"
#include "core/stats.h"
#include "noise/allan.h"
#include "noise/allan_covariance.h"
#include "noise/processes.h"

namespace gyrosid {

// --- structures -------------------------------------------------------------------------------------------

int NoiseStructure::parameters() const {
  return quantization + filter + white + flicker + random_walk + ramp + 2 * gauss_markov;
}

std::string NoiseStructure::name() const {
  std::vector<std::string> parts;
  if (quantization) parts.emplace_back("Q");
  if (filter) parts.emplace_back("F");
  if (white) parts.emplace_back("N");
  if (flicker) parts.emplace_back("B");
  if (random_walk) parts.emplace_back("K");
  if (ramp) parts.emplace_back("R");
  for (int i = 0; i < gauss_markov; ++i) parts.emplace_back("GM");
  return parts.empty() ? "none" : join(parts, "+");
}

NoiseStructure NoiseStructure::parse(std::string_view text) {
  NoiseStructure s;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t plus = std::min(text.find('+', start), text.size());
    const std::string_view term = text.substr(start, plus - start);
    bool* flag = term == "Q" ? &s.quantization : term == "F" ? &s.filter : term == "N" ? &s.white : term == "B" ? &s.flicker
               : term == "K" ? &s.random_walk : term == "R" ? &s.ramp : nullptr;
    if (flag && !*flag) {
      *flag = true;
    } else if (term == "GM") {
      ++s.gauss_markov;
    } else {
      fail("noise terms '", text, "': '", term, "' is ", flag ? "given twice" : "not a term",
           " (terms: Q quantization, F low-pass filter, N white/angle random walk, B flicker/bias instability, K rate random walk, R rate ramp, "
           "GM Gauss-Markov - joined by '+', GM repeated for more; or auto)");
    }
    start = plus + 1;
  }
  return s;
}

NoiseStructure NoiseStructure::full(int gauss_markov) { return {true, true, true, true, true, true, gauss_markov}; }

std::string NoiseIdOptions::validate() const {
  if (terms != "auto") {
    try {
      if (NoiseStructure::parse(terms).parameters() == 0) return "terms: no term given";
    } catch (const Error& e) {
      return e.what();
    }
  }
  if (max_gauss_markov < 0 || max_gauss_markov > 3) return "max_gauss_markov must be in [0, 3]";
  if (!(max_tau_fraction > 0 && max_tau_fraction <= 0.5)) return "max_tau_fraction must be in (0, 0.5]";
  if (!(min_tau_s >= 0)) return "min_tau_s must be >= 0 (0: detected)";
  if (!(max_left_out_tau_s >= 0)) return "max_left_out_tau_s must be >= 0";
  if (!(left_out_alpha > 0 && left_out_alpha < 0.5)) return "left_out_alpha must be in (0, 0.5)";
  if (!(confidence > 0 && confidence < 1)) return "confidence must be in (0, 1)";
  return "";
}

namespace {

// The criterion's price of a parameter: the chi^2_1 quantile at 0.99 - a term is kept when it lowers chi^2
// by more than a 1 % test would allow by chance.
constexpr double kSelectionPenalty = 6.634896601021214;
// The level of the J test (chi^2 of the fit on its degrees of freedom) below which a structure is inadequate.
constexpr double kAdequacyLevel = 0.01;

// --- the linear part: one column per term, its Allan variance per unit variance -----------------------------

enum class Kind { quantization, filter, white, flicker, random_walk, ramp, gauss_markov };

struct Column {
  Kind kind;
  int markov = -1;  // index of its correlation time
};

std::vector<Column> columns_of(const NoiseStructure& s) {
  std::vector<Column> c;
  if (s.quantization) c.push_back({Kind::quantization});
  if (s.filter) c.push_back({Kind::filter});
  if (s.white) c.push_back({Kind::white});
  if (s.flicker) c.push_back({Kind::flicker});
  if (s.random_walk) c.push_back({Kind::random_walk});
  if (s.ramp) c.push_back({Kind::ramp});
  for (int i = 0; i < s.gauss_markov; ++i) c.push_back({Kind::gauss_markov, i});
  return c;
}

double unit_allan_variance(const Column& c, double tau, const std::vector<double>& markov_tau) {
  switch (c.kind) {
    case Kind::quantization: return 3.0 / (tau * tau);
    case Kind::filter: return -3.0 / (tau * tau);
    case Kind::white: return 1.0 / tau;
    case Kind::flicker: return kFlickerAllanFactor;
    case Kind::random_walk: return tau / 3.0;
    case Kind::ramp: return tau * tau / 2.0;
    case Kind::gauss_markov: return gauss_markov_allan_variance(1.0, markov_tau[static_cast<std::size_t>(c.markov)], tau);
  }
  return 0.0;
}

// Octave moments: Allan variances at m = 1, 2, 4, ... up to the longest fitted tau.
struct Moments {
  std::vector<std::size_t> m;
  std::vector<double> tau, s;
  std::size_t n = 0;
  double dt = 0.0;
  std::size_t size() const { return m.size(); }
};

Moments octave_moments(const AllanPhase& phase, double max_tau_fraction, bool robust) {
  Moments mo;
  mo.n = phase.samples();
  mo.dt = phase.dt_s();
  for (std::size_t m = 1; static_cast<double>(m) <= max_tau_fraction * static_cast<double>(mo.n) && 2 * m < mo.n; m *= 2) {
    mo.m.push_back(m);
    mo.tau.push_back(static_cast<double>(m) * mo.dt);
    mo.s.push_back(robust ? phase.robust_variance(m) : phase.variance(m));
  }
  if (mo.size() < 3) fail("noise identification: ", mo.n, " samples give ", mo.size(), " octave averaging times up to a tenth of the record; need 3");
  if (*std::max_element(mo.s.begin(), mo.s.end()) <= 0) fail("noise identification: the rate is constant (every Allan variance is zero)");
  return mo;
}

struct Fit {
  NoiseStructure structure;
  std::vector<double> markov_tau;  // ascending
  Eigen::VectorXd v;               // variance per column of columns_of(structure)
  double chi2 = INFINITY;
};

CompositeNoise composite_of(const Fit& f) {
  CompositeNoise c;
  const auto cols = columns_of(f.structure);
  if (f.v.size() != static_cast<Eigen::Index>(cols.size())) return c;  // not fitted (no room for a correlation time)
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const double value = std::sqrt(std::max(0.0, f.v(static_cast<Eigen::Index>(k))));
    switch (cols[k].kind) {
      case Kind::quantization: c.quantization = value; break;
      case Kind::filter: c.filter = value; break;
      case Kind::white: c.white = value; break;
      case Kind::flicker: c.flicker = value; break;
      case Kind::random_walk: c.random_walk = value; break;
      case Kind::ramp: c.ramp = value; break;
      case Kind::gauss_markov:
        if (value > 0) c.gauss_markov.push_back({value, f.markov_tau[static_cast<std::size_t>(cols[k].markov)]});
        break;
    }
  }
  return c;
}

// The weighted problem on the band [lo, end) of the moments: whitened by the Cholesky factor of the block of
// the covariance.
class Gls {
 public:
  Gls(const Moments& mo, const Eigen::MatrixXd& cov, std::size_t lo) : mo_(mo), lo_(lo) {
    const auto k = static_cast<Eigen::Index>(mo.size() - lo);
    Eigen::MatrixXd block = cov.block(static_cast<Eigen::Index>(lo), static_cast<Eigen::Index>(lo), k, k);
    // Jitter only if round-off made the block indefinite.
    for (double jitter = 0.0;; jitter = jitter == 0.0 ? 1e-12 : 10.0 * jitter) {
      llt_.compute(block + jitter * block.diagonal().mean() * Eigen::MatrixXd::Identity(k, k));
      if (llt_.info() == Eigen::Success || jitter > 1e-3) break;
    }
    s_ = llt_.matrixL().solve(Eigen::Map<const Eigen::VectorXd>(mo.s.data() + lo, k));
  }
  std::size_t lo() const { return lo_; }
  Eigen::Index size() const { return s_.size(); }
  double tau(Eigen::Index i) const { return mo_.tau[lo_ + static_cast<std::size_t>(i)]; }
  Eigen::MatrixXd whiten(const Eigen::MatrixXd& x) const { return llt_.matrixL().solve(x); }

  // chi2 of the structure at these correlation times; v: the non-negative variances.
  double solve(const NoiseStructure& s, const std::vector<double>& markov_tau, Eigen::VectorXd* v) const {
    const auto cols = columns_of(s);
    Eigen::MatrixXd g(size(), static_cast<Eigen::Index>(cols.size()));
    for (Eigen::Index i = 0; i < size(); ++i)
      for (std::size_t k = 0; k < cols.size(); ++k) g(i, static_cast<Eigen::Index>(k)) = unit_allan_variance(cols[k], tau(i), markov_tau);
    Eigen::MatrixXd a = whiten(g);
    Eigen::VectorXd scale = a.colwise().norm().transpose();
    for (Eigen::Index k = 0; k < a.cols(); ++k) {
      if (!(scale(k) > 0)) scale(k) = 1.0;
      a.col(k) /= scale(k);
    }
    const Eigen::VectorXd x = nnls(a, s_);
    if (v) *v = x.cwiseQuotient(scale);
    return (a * x - s_).squaredNorm();
  }

 private:
  const Moments& mo_;
  std::size_t lo_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd s_;
};

// The structure fitted on the band: the correlation times searched in [t_lo, t_hi] (log grid, then refined),
// the variances by NNLS at each.
Fit fit_structure(const Gls& gls, const NoiseStructure& s, double t_lo, double t_hi) {
  Fit best;
  best.structure = s;
  auto evaluate = [&](std::vector<double> taus) {
    std::sort(taus.begin(), taus.end());
    Eigen::VectorXd v;
    const double chi2 = gls.solve(s, taus, &v);
    if (chi2 < best.chi2) best.chi2 = chi2, best.v = v, best.markov_tau = taus;
    return chi2;
  };
  const int k = s.gauss_markov;
  if (k == 0) {
    evaluate({});
    return best;
  }
  if (!(t_hi > t_lo)) return best;  // no room for a correlation time: chi2 stays infinite
  const double a = std::log(t_lo), b = std::log(t_hi);
  const int grid = k == 1 ? 48 : k == 2 ? 20 : 10;
  auto at = [&](int i) { return std::exp(a + (b - a) * i / (grid - 1)); };
  std::vector<int> index(static_cast<std::size_t>(k), 0);
  // Every combination of distinct, ascending grid points.
  std::function<void(int, int)> visit = [&](int depth, int from) {
    if (depth == k) {
      std::vector<double> taus;
      for (int i : index) taus.push_back(at(i));
      evaluate(taus);
      return;
    }
    for (int i = from; i < grid; ++i) index[static_cast<std::size_t>(depth)] = i, visit(depth + 1, i + 1);
  };
  visit(0, 0);
  BoundedSearchOptions search;
  search.max_evaluations = 60 * k;
  search.xtol_abs = 1e-4;
  std::vector<double> start;
  for (double t : best.markov_tau) start.push_back(std::log(t));
  minimize_bounded(
      [&](const std::vector<double>& x) {
        std::vector<double> taus;
        for (double v : x) taus.push_back(std::exp(v));
        return evaluate(taus);
      },
      start, std::vector<double>(start.size(), a), std::vector<double>(start.size(), b), search);
  return best;
}

// The covariance under which the moments are weighted: the model's, over the robust estimate's efficiency.
// No moment is taken as more precise than 1e-6 of its value (a noise-free curve - a pure ramp - has none).
Eigen::MatrixXd moment_covariance(const CompositeNoise& model, const Moments& mo, bool robust) {
  Eigen::MatrixXd cov = allan_variance_covariance(model, mo.m, mo.n, mo.dt);
  if (robust) cov /= kRobustAllanEfficiency;
  for (std::size_t j = 0; j < mo.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    cov(jj, jj) = std::max(cov(jj, jj), std::pow(1e-6 * mo.s[j], 2));
  }
  return cov;
}

// The starting weight: independent moments with white-noise degrees of freedom (NIST SP 1065).
Eigen::MatrixXd starting_covariance(const Moments& mo) {
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(mo.size()), static_cast<Eigen::Index>(mo.size()));
  for (std::size_t j = 0; j < mo.size(); ++j) {
    const double edf = std::max(1.0, allan_edf(0, static_cast<double>(mo.n + 1), static_cast<double>(mo.m[j])));
    cov(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) = 2.0 * mo.s[j] * mo.s[j] / edf;
  }
  return cov;
}

struct Band {
  std::size_t lo = 0;
  double t_lo = 0.0, t_hi = 0.0;  // the correlation times' bounds
};

// A Gauss-Markov correlation time is resolved by the band only from twice its shortest tau (faster, the
// process is white within the band) and at least two samples; at most the record length.
Band band_from(const Moments& mo, std::size_t lo) {
  return {lo, 2.0 * std::max(mo.dt, mo.tau[lo]), static_cast<double>(mo.n) * mo.dt};
}

// Fits `s` with weights iterated to the fixed point Sigma = Sigma(model fitted under Sigma); the fit returned
// is made under the covariance left in `cov`.
Fit iterate_weights(const Moments& mo, Eigen::MatrixXd& cov, const NoiseStructure& s, const Band& band, bool robust, int iterations) {
  Fit fit = fit_structure(Gls(mo, cov, band.lo), s, band.t_lo, band.t_hi);
  std::vector<double> previous;
  for (int it = 0; it < iterations && std::isfinite(fit.chi2); ++it) {
    const CompositeNoise model = composite_of(fit);
    std::vector<double> curve;
    for (double t : mo.tau) curve.push_back(model.allan_variance(t));
    if (*std::max_element(curve.begin(), curve.end()) <= 0) break;
    double change = previous.empty() ? INFINITY : 0.0;
    for (std::size_t j = 0; j < curve.size() && !previous.empty(); ++j) change = std::max(change, std::abs(curve[j] / previous[j] - 1.0));
    if (change < 1e-2) break;  // a 1 % change in the weights moves the estimates by far less than their sigma
    previous = curve;
    cov = moment_covariance(model, mo, robust);
    fit = fit_structure(Gls(mo, cov, band.lo), s, band.t_lo, band.t_hi);
  }
  return fit;
}

// The shortest taus left out while Hansen's C statistic says their moment disagrees with the rest.
std::size_t detect_lower_limit(const Moments& mo, const Eigen::MatrixXd& cov, const NoiseStructure& full, const NoiseIdOptions& o,
                               std::vector<double>* statistics) {
  const double threshold = stats::chi2_quantile(1.0 - o.left_out_alpha, 1.0);
  std::size_t lo = 0;
  while (lo + 5 <= mo.size() && mo.tau[lo + 1] <= o.max_left_out_tau_s) {  // four moments left at least
    const Band reduced = band_from(mo, lo + 1);
    const double with = fit_structure(Gls(mo, cov, lo), full, reduced.t_lo, reduced.t_hi).chi2;
    const double without = fit_structure(Gls(mo, cov, lo + 1), full, reduced.t_lo, reduced.t_hi).chi2;
    const double c = with - without;
    if (!(c > threshold)) break;
    statistics->push_back(c);
    ++lo;
  }
  return lo;
}

// Every structure with fewer parameters than moments in the band, under one weight; best first by
// chi2 + penalty p.
std::vector<NoiseCandidate> rank_structures(const Gls& gls, const Band& band, int max_gm, double penalty) {
  std::vector<NoiseCandidate> out;
  for (int mask = 0; mask < 64; ++mask) {
    if ((mask & 3) == 3) continue;  // quantization and filter: one column of either sign
    for (int gm = 0; gm <= max_gm; ++gm) {
      const NoiseStructure s{(mask & 1) != 0, (mask & 2) != 0, (mask & 4) != 0, (mask & 8) != 0, (mask & 16) != 0, (mask & 32) != 0, gm};
      if (s.parameters() == 0 || s.parameters() >= gls.size()) continue;
      const Fit f = fit_structure(gls, s, band.t_lo, band.t_hi);
      if (std::isfinite(f.chi2)) out.push_back({s, f.chi2, f.chi2 + penalty * s.parameters()});
    }
  }
  if (out.empty()) fail("noise identification: ", gls.size(), " averaging times in the band leave no model with fewer parameters");
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.criterion < b.criterion; });
  return out;
}

// The structure: every one ranked under the fullest model's weight, the best few ranked again each under its
// own weight (the covariance a model implies is the one its chi2 must be judged by: under a richer model's
// weight, a slow term's misfit at the long taus looks small).
std::vector<NoiseCandidate> select_structure(const Moments& mo, const Eigen::MatrixXd& full_cov, const Band& band, int max_gm, bool robust) {
  std::vector<NoiseCandidate> ranked = rank_structures(Gls(mo, full_cov, band.lo), band, max_gm, kSelectionPenalty);
  ranked.resize(std::min<std::size_t>(ranked.size(), 12));
  const auto moments = static_cast<int>(mo.size() - band.lo);
  for (auto& c : ranked) {
    Eigen::MatrixXd own = full_cov;
    c.chi2 = iterate_weights(mo, own, c.structure, band, robust, 1).chi2;  // one step to its own weight
    c.criterion = c.chi2 + kSelectionPenalty * c.structure.parameters();
    const int dof = moments - c.structure.parameters();
    c.adequate = dof <= 0 || 1.0 - stats::chi2_cdf(c.chi2, dof) >= kAdequacyLevel;
  }
  // Adequate first (a model the J test does not reject), then the least criterion.
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    return a.adequate != b.adequate ? a.adequate : a.criterion < b.criterion;
  });
  return ranked;
}

// theta: the variance of every column (those at their bound of zero included, so that a term the band
// barely determines still gets an interval), then the log correlation time of each Gauss-Markov term with a
// positive variance.
std::string column_name(const Column& c);

std::vector<NoiseCoordinate> coordinates_of(const Fit& f) {
  std::vector<NoiseCoordinate> out;
  const auto cols = columns_of(f.structure);
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const bool markov = cols[k].kind == Kind::gauss_markov;
    out.push_back({markov ? "GM" : column_name(cols[k]), markov ? f.markov_tau[static_cast<std::size_t>(cols[k].markov)] : 0.0, 0.0});
  }
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const double v = f.v(static_cast<Eigen::Index>(k));
    if (cols[k].kind == Kind::gauss_markov && v > 0) out.push_back({"GM tau", f.markov_tau[static_cast<std::size_t>(cols[k].markov)], v});
  }
  return out;
}

// (J' Sigma^-1 J)^-1 by the pseudo-inverse of the whitened Jacobian (a direction the band cannot determine
// gets no spurious precision).
Eigen::MatrixXd theta_covariance(const Gls& gls, const std::vector<NoiseCoordinate>& theta) {
  Eigen::MatrixXd j(gls.size(), static_cast<Eigen::Index>(theta.size()));
  for (Eigen::Index i = 0; i < gls.size(); ++i)
    for (std::size_t k = 0; k < theta.size(); ++k) j(i, static_cast<Eigen::Index>(k)) = theta[k].allan_variance_gradient(gls.tau(i));
  const Eigen::MatrixXd jw = gls.whiten(j);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jw, Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(sv.size());
  for (Eigen::Index k = 0; k < sv.size(); ++k)
    if (sv(k) > 1e-10 * sv(0)) inv(k) = 1.0 / (sv(k) * sv(k));
  return svd.matrixV() * inv.asDiagonal() * svd.matrixV().transpose();
}

std::string column_name(const Column& c) {
  switch (c.kind) {
    case Kind::quantization: return "Q";
    case Kind::filter: return "F";
    case Kind::white: return "N";
    case Kind::flicker: return "B";
    case Kind::random_walk: return "K";
    case Kind::ramp: return "R";
    case Kind::gauss_markov: return str_cat("GM", c.markov + 1, " sigma");
  }
  return "";
}

// A coefficient sqrt(v) from its variance v: standard error by the delta method, interval chi-square with
// Satterthwaite's degrees of freedom 2 v^2 / var(v) (log-normal on v below one degree of freedom, where the
// chi-square quantiles run away).
NoiseParameter coefficient(const std::string& name, double v, double var_v, double confidence) {
  NoiseParameter p{name, std::sqrt(v), 0.0, std::sqrt(v), std::sqrt(v)};
  if (!(var_v > 0)) return p;
  p.sigma = std::sqrt(var_v) / (2.0 * std::sqrt(v));
  const double dof = 2.0 * v * v / var_v, tail = 0.5 * (1.0 - confidence);
  if (dof > 1e7) {
    const double z = stats::normal_quantile(1.0 - tail) * std::sqrt(var_v);
    p.low = std::sqrt(std::max(0.0, v - z)), p.high = std::sqrt(v + z);
  } else if (dof >= 1.0) {
    p.low = std::sqrt(dof * v / stats::chi2_quantile(1.0 - tail, dof));
    p.high = std::sqrt(dof * v / stats::chi2_quantile(tail, dof));
  } else {
    const double spread = stats::normal_quantile(1.0 - tail) * std::sqrt(var_v) / v;
    p.low = std::sqrt(v * std::exp(-spread)), p.high = std::sqrt(v * std::exp(spread));
  }
  return p;
}

std::vector<NoiseParameter> parameters_of(const Fit& f, const std::vector<NoiseCoordinate>& theta, const Eigen::MatrixXd& cov, double confidence) {
  const auto cols = columns_of(f.structure);
  const double z = stats::normal_quantile(0.5 + 0.5 * confidence);
  std::vector<NoiseParameter> out;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    const double v = f.v(kk), var_v = cov(kk, kk);
    const std::string name = column_name(cols[k]);
    if (v > 0) {
      out.push_back(coefficient(name, v, var_v, confidence));
    } else {
      // At its bound: the band resolves the variance to sqrt(var v); the one-sided upper limit on the coefficient.
      const double sd = std::sqrt(std::max(0.0, var_v));
      out.push_back({name, 0.0, std::sqrt(sd), 0.0, std::sqrt(z * sd)});
    }
    if (cols[k].kind != Kind::gauss_markov || !(v > 0)) continue;
    const double tau = f.markov_tau[static_cast<std::size_t>(cols[k].markov)];
    for (std::size_t r = cols.size(); r < theta.size(); ++r) {
      if (theta[r].tau_s != tau) continue;
      const double sd = std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(r))));
      out.push_back({str_cat("GM", cols[k].markov + 1, " tau"), tau, tau * sd, tau * std::exp(-z * sd), tau * std::exp(z * sd)});
    }
  }
  return out;
}

}  // namespace

double NoiseCoordinate::allan_variance_gradient(double tau) const {
  if (term == "GM tau") {
    const double h = 1e-5;
    return variance * (gauss_markov_allan_variance(1.0, tau_s * std::exp(h), tau) - gauss_markov_allan_variance(1.0, tau_s * std::exp(-h), tau)) / (2.0 * h);
  }
  if (term == "GM") return gauss_markov_allan_variance(1.0, tau_s, tau);
  if (term == "Q") return 3.0 / (tau * tau);
  if (term == "F") return -3.0 / (tau * tau);
  if (term == "N") return 1.0 / tau;
  if (term == "B") return kFlickerAllanFactor;
  if (term == "K") return tau / 3.0;
  if (term == "R") return tau * tau / 2.0;
  fail("noise coordinate: unknown term '", term, "'");
}

double NoiseIdentification::allan_variance_sigma(double tau) const {
  if (covariance.size() == 0) return 0.0;
  Eigen::RowVectorXd g(static_cast<Eigen::Index>(coordinates.size()));
  for (std::size_t k = 0; k < coordinates.size(); ++k) g(static_cast<Eigen::Index>(k)) = coordinates[k].allan_variance_gradient(tau);
  return std::sqrt(std::max(0.0, (g * covariance * g.transpose())(0, 0)));
}

namespace {

std::string left_out_sentence(const Moments& mo, std::size_t lo, const CompositeNoise& model, const std::vector<double>& statistics, double threshold) {
  if (lo == 0) return "";
  // Data over model (Allan deviation) at each left-out tau: the largest departure, and its sign everywhere. A
  // filter term describes the filter beyond its span only, so the comparison is with the model without it.
  CompositeNoise unfiltered = model;
  unfiltered.filter = 0.0;
  double worst = 1.0, worst_tau = mo.tau[0];
  int below = 0;
  for (std::size_t j = 0; j < lo; ++j) {
    const double ratio = std::sqrt(mo.s[j] / unfiltered.allan_variance(mo.tau[j]));
    below += ratio < 1.0;
    if (std::abs(std::log(ratio)) > std::abs(std::log(worst))) worst = ratio, worst_tau = mo.tau[j];
  }
  const char* cause = below == static_cast<int>(lo) ? "below the model: the sensor's anti-alias filter or decimation correlates neighbouring samples"
                      : below == 0                  ? "above the model: noise faster than the model's terms (aliasing, a tone, or quantization of the rate)"
                                                    : "on both sides of the model: structure faster than its terms (a filter, a tone)";
  std::vector<std::string> c;
  for (double s : statistics) c.push_back(format_significant(s, 3));
  return str_cat("averaging times ", format_significant(mo.tau[0], 3), (lo > 1 ? str_cat("-", format_significant(mo.tau[lo - 1], 3)) : ""),
                 " s left out: the Allan deviation there departs from the model by up to ", format_significant(std::abs(worst - 1.0) * 100.0, 2),
                 " % (at ", format_significant(worst_tau, 3), " s), ", cause, " (C statistics ", join(c, ", "), " against ",
                 format_significant(threshold, 3), "); the fit starts at ", format_significant(mo.tau[lo], 3), " s");
}

void add_warnings(NoiseIdentification& r, const AllanPhase& phase, const Moments& mo) {
  if (r.p_value < 0.01) {
    std::vector<std::string> worst;
    for (const auto& p : r.points)
      if (p.in_band && std::abs(p.z) > 3.0) worst.push_back(str_cat(format_significant(p.tau_s, 3), " s (z ", format_significant(p.z, 2), ")"));
    r.warnings.push_back(str_cat("the model does not fit the Allan variances in the band (chi2 ", format_significant(r.chi2, 3), " on ", r.dof,
                                 " degrees of freedom, p ", format_significant(r.p_value, 2), ")",
                                 worst.empty() ? "" : "; worst at " + join(worst, ", ")));
  }
  for (const auto& gm : r.model.gauss_markov) {
    const double lo = 2.0 * std::max(r.dt_s, r.fit_tau_low_s), hi = static_cast<double>(r.samples) * r.dt_s;
    if (gm.tau_s < 1.01 * lo || gm.tau_s > 0.99 * hi) {
      r.warnings.push_back(str_cat("a Gauss-Markov correlation time sits at its bound (", format_significant(gm.tau_s, 3), " s in [",
                                   format_significant(lo, 3), ", ", format_significant(hi, 3), "] s): the band does not resolve it"));
    }
  }
  if (!r.robust) {
    const double ratio = mo.s[0] / phase.robust_variance(mo.m[0]);
    if (ratio > 1.3) {
      r.warnings.push_back(str_cat("the Allan variance at ", format_significant(mo.tau[0], 3), " s is ", format_significant(ratio, 3),
                                   " times its robust estimate: the recording has outliers (spikes); --robust estimates without them"));
    }
  }
}

}  // namespace

NoiseIdentification identify_noise(std::span<const double> rate, double dt_s, const NoiseIdOptions& o) {
  return identify_noise(AllanPhase(rate, dt_s), o);
}

NoiseIdentification identify_noise(const AllanPhase& phase, const NoiseIdOptions& o) {
  if (const auto problem = o.validate(); !problem.empty()) fail("noise identification: ", problem);
  const Moments mo = octave_moments(phase, o.max_tau_fraction, o.robust);
  const NoiseStructure given = o.terms == "auto" ? NoiseStructure{} : NoiseStructure::parse(o.terms);
  const int max_gm = o.terms == "auto" ? o.max_gauss_markov : std::max(o.max_gauss_markov, given.gauss_markov);
  const NoiseStructure full = NoiseStructure::full(max_gm);

  // Weights under the fullest model on every tau; then the band; then the weights again on the band.
  Eigen::MatrixXd cov = starting_covariance(mo);
  std::size_t lo = 0;
  while (lo + 1 < mo.size() && o.min_tau_s > 0 && mo.tau[lo] < o.min_tau_s * (1.0 - 1e-9)) ++lo;
  iterate_weights(mo, cov, full, band_from(mo, lo), o.robust, 6);
  std::vector<double> statistics;
  if (o.min_tau_s == 0) lo = detect_lower_limit(mo, cov, full, o, &statistics);
  const Band band = band_from(mo, lo);
  const Fit full_fit = iterate_weights(mo, cov, full, band, o.robust, 4);

  // The structure: given, or chosen under the fullest model's weight; then its own weight.
  NoiseIdentification r;
  if (o.terms == "auto") r.candidates = select_structure(mo, cov, band, max_gm, o.robust);
  const NoiseStructure chosen = o.terms == "auto" ? r.candidates.front().structure : given;
  const Fit fit = chosen == full ? full_fit : iterate_weights(mo, cov, chosen, band, o.robust, 4);
  const Gls final_gls(mo, cov, lo);

  r.model = composite_of(fit);
  r.structure = chosen;
  r.samples = mo.n;
  r.dt_s = mo.dt;
  r.robust = o.robust;
  r.fit_tau_low_s = mo.tau[lo];
  r.fit_tau_high_s = mo.tau.back();
  r.chi2 = fit.chi2;
  r.coordinates = coordinates_of(fit);
  r.dof = static_cast<int>(final_gls.size()) - chosen.parameters();
  r.p_value = r.dof > 0 ? 1.0 - stats::chi2_cdf(r.chi2, r.dof) : 1.0;
  r.covariance = theta_covariance(final_gls, r.coordinates);
  // The data scatter more than the model's covariance says when chi2 exceeds its degrees of freedom: the
  // covariance is widened by that ratio (never narrowed), as a quasi-likelihood dispersion.
  r.dispersion = r.dof >= 3 ? std::max(1.0, r.chi2 / r.dof) : 1.0;
  r.covariance *= r.dispersion;
  r.parameters = parameters_of(fit, r.coordinates, r.covariance, o.confidence);
  for (std::size_t j = 0; j < mo.size(); ++j) {
    const double fitted = r.model.allan_variance(mo.tau[j]);
    const auto jj = static_cast<Eigen::Index>(j);
    r.points.push_back({mo.tau[j], mo.s[j], fitted, (mo.s[j] - fitted) / std::sqrt(cov(jj, jj)), j >= lo});
  }
  r.left_out = left_out_sentence(mo, lo, r.model, statistics, stats::chi2_quantile(1.0 - o.left_out_alpha, 1.0));
  add_warnings(r, phase, mo);
  return r;
}

}  // namespace gyrosid
