#include "noise/allan_covariance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/error.h"

namespace gyrosid {
namespace {

constexpr std::array<double, 3> kG = {1.0, -2.0, 1.0};
constexpr std::array<double, 8> kGaussX = {-0.96028985649753618, -0.79666647741362673, -0.52553240991632899, -0.18343464249564978,
                                           0.18343464249564978,  0.52553240991632899,  0.79666647741362673,  0.96028985649753618};
constexpr std::array<double, 8> kGaussW = {0.10122853629037669, 0.22238103445337434, 0.31370664587788705, 0.36268378337836177,
                                           0.36268378337836177, 0.31370664587788705, 0.22238103445337434, 0.10122853629037669};
constexpr std::int64_t kExact = 4;  // lags summed term by term next to every kink

// The lag sum for one pair of cluster sizes (m1, m2).
class LagSum {
 public:
  LagSum(const CompositeNoise& model, std::int64_t m1, std::int64_t m2, std::int64_t k1, std::int64_t k2, double dt)
      : full_(model), tail_(model), m1_(m1), m2_(m2), k1_(k1), k2_(k2), dt_(dt) {
    // White, quantization and random walk couple two second differences only where their supports overlap:
    // outside it their phase covariances cancel exactly, so only the slowly decaying terms are evaluated
    // there (their large |h|^k values would otherwise cancel in floating point to noise).
    tail_.white = tail_.random_walk = tail_.quantization = tail_.filter = 0.0;
    mu_product_ = model.ramp * model.ramp * std::pow(static_cast<double>(m1) * dt, 2) * std::pow(static_cast<double>(m2) * dt, 2);
  }

  // c(j) at a real lag j (quantization excluded).
  double c(double j) const {
    const bool overlap = j > -2.0 * static_cast<double>(m2_) && j < 2.0 * static_cast<double>(m1_);
    const CompositeNoise& model = overlap ? full_ : tail_;
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) {
      double inner = 0.0;  // the second difference over the larger step first, for the fewest lost digits
      for (int b = 0; b < 3; ++b) inner += kG[b] * model.phase_covariance(dt_ * (j + b * static_cast<double>(m2_) - a * static_cast<double>(m1_)));
      sum += kG[a] * inner;
    }
    return sum;
  }
  double pairs(double j) const {
    return std::max(0.0, std::min(static_cast<double>(k1_), static_cast<double>(k2_) - j) - std::max(0.0, -j));
  }
  double mu_product() const { return mu_product_; }
  double term(double j) const {
    const double cj = c(j);
    return pairs(j) * (2.0 * cj * cj + 4.0 * mu_product_ * cj);
  }

  // sum_{j = a}^{b} term(j).
  double segment(std::int64_t a, std::int64_t b) const {
    double s = 0.0;
    if (b - a < 4 * kExact) {
      for (std::int64_t j = a; j <= b; ++j) s += term(static_cast<double>(j));
      return s;
    }
    for (std::int64_t j = a; j < a + kExact; ++j) s += term(static_cast<double>(j));
    for (std::int64_t j = b - kExact + 1; j <= b; ++j) s += term(static_cast<double>(j));
    // sum_{j=lo}^{hi} f(j) = int_lo^hi f + (f(lo) + f(hi))/2 + (f'(hi) - f'(lo))/12 + ...
    const auto lo = static_cast<double>(a + kExact), hi = static_cast<double>(b - kExact);
    const double f_lo = term(lo), f_hi = term(hi);
    const double d_lo = (term(lo + 0.5) - term(lo - 0.5)), d_hi = (term(hi + 0.5) - term(hi - 0.5));
    return s + graded_integral(lo, hi) + 0.5 * (f_lo + f_hi) + (d_hi - d_lo) / 12.0;
  }

 private:
  // int_lo^hi term, on pieces that grow eightfold away from both ends (where the exponential and
  // logarithmic terms vary fastest), 8-point Gauss-Legendre on each.
  double graded_integral(double lo, double hi) const {
    std::vector<double> cuts = {lo};
    const double mid = 0.5 * (lo + hi);
    for (double step = 1.0; lo + step < mid; step *= 8.0) cuts.push_back(lo + step);
    cuts.push_back(mid);
    std::vector<double> upper;
    for (double step = 1.0; hi - step > mid; step *= 8.0) upper.push_back(hi - step);
    for (auto it = upper.rbegin(); it != upper.rend(); ++it) cuts.push_back(*it);
    cuts.push_back(hi);
    double s = 0.0;
    for (std::size_t i = 1; i < cuts.size(); ++i) {
      const double half = 0.5 * (cuts[i] - cuts[i - 1]), centre = 0.5 * (cuts[i] + cuts[i - 1]);
      if (half <= 0) continue;
      for (std::size_t q = 0; q < kGaussX.size(); ++q) s += half * kGaussW[q] * term(centre + half * kGaussX[q]);
    }
    return s;
  }

  CompositeNoise full_, tail_;
  std::int64_t m1_, m2_, k1_, k2_;
  double dt_;
  double mu_product_ = 0.0;
};

// The reach of the slowly decaying terms beyond the overlapping supports, in lags.
std::int64_t tail_lags(const CompositeNoise& model, std::int64_t m_max, double dt) {
  double reach = 0.0;
  if (model.flicker > 0) reach = 16.0 * static_cast<double>(m_max);  // c ~ 1/h^2 there: c^2 summed beyond falls as 1/h^3
  for (const auto& gm : model.gauss_markov) reach = std::max(reach, 25.0 * gm.tau_s / dt);
  return static_cast<std::int64_t>(std::min(reach, 1e15));
}

double pair_sum(const CompositeNoise& model, std::int64_t m1, std::int64_t m2, std::int64_t n, double dt) {
  const std::int64_t k1 = n + 1 - 2 * m1, k2 = n + 1 - 2 * m2;
  const LagSum sum(model, m1, m2, k1, k2, dt);
  const std::int64_t reach = tail_lags(model, std::max(m1, m2), dt);
  const std::int64_t j_lo = std::max(-(k1 - 1), -2 * m2 - reach), j_hi = std::min(k2 - 1, 2 * m1 + reach);
  if (j_lo > j_hi) return 0.0;
  // Kinks: where one of the nine lags crosses zero, and where the count of index pairs bends.
  std::vector<std::int64_t> kinks = {j_lo, j_hi + 1, 0, k2 - k1, -2 * m2, 2 * m1};
  for (std::int64_t a = 0; a < 3; ++a)
    for (std::int64_t b = 0; b < 3; ++b) kinks.push_back(a * m1 - b * m2);
  std::erase_if(kinks, [&](std::int64_t j) { return j < j_lo || j > j_hi + 1; });
  std::sort(kinks.begin(), kinks.end());
  kinks.erase(std::unique(kinks.begin(), kinks.end()), kinks.end());
  double s = 0.0;
  for (std::size_t i = 1; i < kinks.size(); ++i) s += sum.segment(kinks[i - 1], kinks[i] - 1);
  // Quantization (white phase) and filter terms covary only where two phase points coincide, j = a m1 - b m2.
  if (model.point_variance() != 0) {
    const double q2 = model.point_variance();
    std::vector<std::pair<std::int64_t, double>> deltas;
    for (std::int64_t a = 0; a < 3; ++a) {
      for (std::int64_t b = 0; b < 3; ++b) {
        const std::int64_t j = a * m1 - b * m2;
        if (j < j_lo || j > j_hi) continue;
        auto it = std::find_if(deltas.begin(), deltas.end(), [&](const auto& d) { return d.first == j; });
        if (it == deltas.end()) it = deltas.insert(deltas.end(), {j, 0.0});
        it->second += kG[static_cast<std::size_t>(a)] * kG[static_cast<std::size_t>(b)] * q2;
      }
    }
    for (const auto& [j, cq] : deltas) {
      const double cs = sum.c(static_cast<double>(j));
      s += sum.pairs(static_cast<double>(j)) * (2.0 * ((cs + cq) * (cs + cq) - cs * cs) + 4.0 * sum.mu_product() * cq);
    }
  }
  return s;
}

}  // namespace

Eigen::MatrixXd allan_variance_covariance(const CompositeNoise& model, std::span<const std::size_t> ms, std::size_t samples, double dt) {
  if (!(dt > 0)) fail("Allan covariance: sample interval ", dt, " s must be positive");
  const auto n = static_cast<std::int64_t>(samples);
  const auto size = static_cast<Eigen::Index>(ms.size());
  Eigen::MatrixXd cov(size, size);
  for (Eigen::Index i = 0; i < size; ++i) {
    for (Eigen::Index k = i; k < size; ++k) {
      const auto m1 = static_cast<std::int64_t>(ms[static_cast<std::size_t>(i)]), m2 = static_cast<std::int64_t>(ms[static_cast<std::size_t>(k)]);
      if (m1 < 1 || m2 < 1 || 2 * std::max(m1, m2) > n) fail("Allan covariance: cluster size ", std::max(m1, m2), " for ", n, " samples");
      const double tau1 = static_cast<double>(m1) * dt, tau2 = static_cast<double>(m2) * dt;
      const double k1 = static_cast<double>(n + 1 - 2 * m1), k2 = static_cast<double>(n + 1 - 2 * m2);
      cov(i, k) = cov(k, i) = pair_sum(model, m1, m2, n, dt) / (4.0 * tau1 * tau1 * tau2 * tau2 * k1 * k2);
    }
  }
  return cov;
}

}  // namespace gyrosid
