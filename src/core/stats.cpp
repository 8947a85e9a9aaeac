#include "core/stats.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace gyrosid::stats {

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) fail("normal_quantile: p = ", p, " is outside (0, 1)");
  // Initial value from a logistic-like rational guess, refined by Newton steps on erfc (quadratic
  // convergence; 1e-15 after a few steps).
  double x = (p < 0.5 ? -1.0 : 1.0) * std::sqrt(-2.0 * std::log(p < 0.5 ? p : 1.0 - p));
  x -= (p < 0.5 ? -1.0 : 1.0) * (2.515517 + 0.802853 * std::abs(x) + 0.010328 * x * x) /
       (1.0 + 1.432788 * std::abs(x) + 0.189269 * x * x + 0.001308 * std::abs(x) * x * x);
  for (int i = 0; i < 6; ++i) {
    const double density = std::exp(-0.5 * x * x) / std::sqrt(2.0 * 3.14159265358979323846);
    if (density == 0.0) break;
    x -= (normal_cdf(x) - p) / density;
  }
  return x;
}

double regularized_gamma_p(double a, double x) {
  if (a <= 0.0) fail("regularized_gamma_p: a = ", a, " must be positive");
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    // P(a,x) = x^a e^-x / Gamma(a+1) * sum_n x^n / ((a+1)...(a+n))
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::exp(log_prefactor) * sum;
  }
  // Q(a,x) by the modified Lentz evaluation of the continued fraction; P = 1 - Q.
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

namespace {
// The continued fraction of I_x(a, b) (DLMF 8.17.22) by the modified Lentz method; converges fast for
// x < (a + 1) / (a + b + 2).
double beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  d = 1.0 / (std::abs(d) < tiny ? tiny : d);
  double f = d;
  for (int m = 1; m < 1000; ++m) {
    for (int half = 0; half < 2; ++half) {  // d_{2m} then d_{2m+1}
      const double num = half == 0 ? m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m))
                                   : -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
      d = 1.0 + num * d;
      d = 1.0 / (std::abs(d) < tiny ? tiny : d);
      c = 1.0 + num / c;
      if (std::abs(c) < tiny) c = tiny;
      f *= c * d;
      if (half == 1 && std::abs(c * d - 1.0) < 1e-15) return f;
    }
  }
  return f;
}
}  // namespace

double regularized_beta(double a, double b, double x) {
  if (!(a > 0.0 && b > 0.0)) fail("regularized_beta: a = ", a, ", b = ", b, " must be positive");
  if (!(x >= 0.0 && x <= 1.0)) fail("regularized_beta: x = ", x, " is outside [0, 1]");
  if (x == 0.0 || x == 1.0) return x;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(log_front) * beta_fraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * beta_fraction(b, a, 1.0 - x) / b;  // I_x(a, b) = 1 - I_{1-x}(b, a)
}

double student_t_two_sided(double t, double dof) {
  if (!(dof > 0.0)) fail("student_t_two_sided: dof = ", dof, " must be positive");
  return regularized_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

double chi2_cdf(double x, double dof) { return regularized_gamma_p(0.5 * dof, 0.5 * x); }

double chi2_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0)) fail("chi2_quantile: p = ", p, " is outside (0, 1)");
  if (!(dof > 0.0)) fail("chi2_quantile: dof = ", dof, " must be positive");
  // Wilson-Hilferty start, then safeguarded Newton on the CDF within a bracket.
  const double z = normal_quantile(p);
  const double k = 2.0 / (9.0 * dof);
  double x = std::max(1e-12, dof * std::pow(1.0 - k + z * std::sqrt(k), 3.0));
  double lo = 0.0, hi = std::max(2.0 * x, dof + 50.0 * std::sqrt(2.0 * dof) + 100.0);
  while (chi2_cdf(hi, dof) < p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double f = chi2_cdf(x, dof) - p;
    if (f > 0) hi = x;
    else lo = x;
    const double log_density =
        (0.5 * dof - 1.0) * std::log(x) - 0.5 * x - 0.5 * dof * std::log(2.0) - std::lgamma(0.5 * dof);
    double next = x - f / std::exp(log_density);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-14 * std::max(1.0, x)) return next;
    x = next;
  }
  return x;
}

}  // namespace gyrosid::stats
