#include "explain/noise_model.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace gyrosid::explain {

std::vector<std::vector<Eigen::Index>> contiguous_runs(const std::vector<Eigen::Index>& rows, const std::vector<int>& segment) {
  std::vector<std::vector<Eigen::Index>> runs;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Eigen::Index i = rows[k];
    const bool joins = k > 0 && i == rows[k - 1] + 1 &&
                       segment[static_cast<std::size_t>(i)] == segment[static_cast<std::size_t>(rows[k - 1])];
    if (!joins) runs.emplace_back();
    runs.back().push_back(i);
  }
  return runs;
}

ArNoiseModel fit_ar(const Eigen::VectorXd& x, const std::vector<std::vector<Eigen::Index>>& runs, int max_order) {
  // Burg recursion on every run at once: f and b are the forward and backward prediction errors.
  std::vector<std::vector<double>> f, b;
  std::size_t total = 0;
  double energy = 0.0;
  for (const auto& run : runs) {
    std::vector<double> v;
    v.reserve(run.size());
    for (Eigen::Index i : run) v.push_back(x(i));
    for (double e : v) energy += e * e;
    total += v.size();
    f.push_back(v);
    b.push_back(v);
  }
  if (total < 10) fail("noise model: too few samples (", total, ")");
  const double n = static_cast<double>(total);
  std::vector<double> a;
  double variance = energy / n;
  ArNoiseModel best{{}, variance};
  double best_bic = n * std::log(variance);
  for (int m = 1; m <= max_order; ++m) {
    double num = 0.0, den = 0.0;
    for (std::size_t r = 0; r < f.size(); ++r) {
      for (std::size_t i = static_cast<std::size_t>(m); i < f[r].size(); ++i) {
        num += f[r][i] * b[r][i - 1];
        den += f[r][i] * f[r][i] + b[r][i - 1] * b[r][i - 1];
      }
    }
    if (!(den > 0)) break;
    const double k = -2.0 * num / den;
    // Levinson update of the coefficients and of the errors.
    std::vector<double> next(static_cast<std::size_t>(m));
    for (int j = 0; j < m - 1; ++j) next[static_cast<std::size_t>(j)] = a[static_cast<std::size_t>(j)] + k * a[static_cast<std::size_t>(m - 2 - j)];
    next[static_cast<std::size_t>(m - 1)] = k;
    a = next;
    for (std::size_t r = 0; r < f.size(); ++r) {
      for (std::size_t i = f[r].size(); i-- > static_cast<std::size_t>(m);) {
        const double fi = f[r][i], bi = b[r][i - 1];
        f[r][i] = fi + k * bi;
        b[r][i] = bi + k * fi;
      }
    }
    variance *= (1.0 - k * k);
    const double bic = n * std::log(variance) + m * std::log(n);
    if (bic < best_bic) best_bic = bic, best = {a, variance};
  }
  return best;
}

Whitener::Whitener(ArNoiseModel model, const std::vector<std::vector<Eigen::Index>>& runs) : model_(std::move(model)) {
  const std::size_t p = static_cast<std::size_t>(model_.order());
  for (const auto& run : runs) {
    for (std::size_t k = p; k < run.size(); ++k) rows_.push_back(run[k]);
  }
  if (rows_.empty()) fail("noise model: no sample has the AR history of order ", p);
}

Eigen::MatrixXd Whitener::apply(const Eigen::MatrixXd& x) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows_.size()), x.cols());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const Eigen::Index i = rows_[r];
    out.row(static_cast<Eigen::Index>(r)) = x.row(i);
    for (std::size_t k = 0; k < model_.a.size(); ++k) out.row(static_cast<Eigen::Index>(r)) += model_.a[k] * x.row(i - 1 - static_cast<Eigen::Index>(k));
  }
  return out;
}

}  // namespace gyrosid::explain
