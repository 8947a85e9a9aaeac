#include "nav/statistics.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/stats.h"

namespace gyrosid::nav {

SampleStats sample_stats(const std::vector<double>& x) {
  SampleStats s;
  if (x.empty()) return s;
  for (double v : x) s.mean += v;
  s.mean /= static_cast<double>(x.size());
  double ss = 0.0;
  for (double v : x) ss += (v - s.mean) * (v - s.mean);
  s.sigma = x.size() > 1 ? std::sqrt(ss / static_cast<double>(x.size() - 1)) : 0.0;
  return s;
}

AndersonDarling anderson_darling_normal(std::vector<double> x) {
  const std::size_t n = x.size();
  if (n < 8) fail("Anderson-Darling: need at least 8 values, got ", n);
  const SampleStats s = sample_stats(x);
  AndersonDarling r;
  if (!(s.sigma > 0)) return r;  // a constant sample is not normal
  std::sort(x.begin(), x.end());
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    // ln Phi(z) and ln(1 - Phi(z)) through erfc, accurate in both tails.
    const double zi = (x[i] - s.mean) / s.sigma, zj = (x[n - 1 - i] - s.mean) / s.sigma;
    const double log_cdf = std::log(0.5 * std::erfc(-zi / std::sqrt(2.0)));
    const double log_sf = std::log(0.5 * std::erfc(zj / std::sqrt(2.0)));
    sum += (2.0 * static_cast<double>(i) + 1.0) * (log_cdf + log_sf);
  }
  const double nn = static_cast<double>(n);
  r.a2 = -nn - sum / nn;
  const double a = r.a2 * (1.0 + 0.75 / nn + 2.25 / (nn * nn));
  r.a2_adjusted = a;
  if (a >= 0.6) r.p_value = std::exp(1.2937 - 5.709 * a + 0.0186 * a * a);
  else if (a >= 0.34) r.p_value = std::exp(0.9177 - 4.279 * a - 1.38 * a * a);
  else if (a >= 0.2) r.p_value = 1.0 - std::exp(-8.318 + 42.796 * a - 59.938 * a * a);
  else r.p_value = 1.0 - std::exp(-13.436 + 101.14 * a - 223.73 * a * a);
  r.p_value = std::clamp(r.p_value, 0.0, 1.0);
  r.normal_at_5_percent = a < 0.752;
  return r;
}

}  // namespace gyrosid::nav
