#include "explain/support_check.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "explain/linear_fit.h"
#include "explain/noise_likelihood.h"

namespace gyrosid::explain {

std::string SupportCheckOptions::validate() const {
  if (!(held_share >= 0 && held_share <= 1)) return str_cat("support check: held_share = ", held_share, " must be in [0, 1]");
  if (!(material > 0 && material < 1)) return str_cat("support check: material = ", material, " must be in (0, 1)");
  if (folds < 2) return str_cat("support check: folds = ", folds, " must be at least 2");
  if (min_fold_samples < 1) return str_cat("support check: min_fold_samples = ", min_fold_samples, " must be at least 1");
  return "";
}

void WhitenedGain::add(const Eigen::VectorXd& r, const Eigen::VectorXd& d) {
  dd += d.squaredNorm(), rd += r.dot(d), rr += r.squaredNorm();
  n += static_cast<std::size_t>(r.size());
}

bool WhitenedGain::testable(double sigma) const {
  return std::sqrt(dd) / std::sqrt(static_cast<double>(std::max<std::size_t>(1, n))) > 0.05 * sigma;
}

double WhitenedGain::z() const {
  const double sigma_h = std::sqrt(rr / std::max<double>(1.0, static_cast<double>(n)));
  return dd > 0 ? (dd + 2.0 * rd) / (2.0 * sigma_h * std::sqrt(dd)) : 0.0;
}

bool heldout_blocks_hold(const ExplainInput& in, const std::vector<char>& outside, const Eigen::VectorXd& c, double held_share) {
  double held = 0.0, all = 0.0;
  std::size_t rows = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    all += c(i) * c(i);
    if (in.confirms(i, outside)) held += c(i) * c(i), ++rows;
  }
  if (!(all > 0)) return true;
  const double fair = static_cast<double>(rows) / static_cast<double>(in.size());
  return held / all >= held_share * fair;
}

namespace {

// The fold's residuals of the model `x`, fitted on every training sample outside the fold.
Eigen::VectorXd fold_residual(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& rest, const Eigen::VectorXd& y_rest,
                              const std::vector<Eigen::Index>& fold) {
  const WhitenedFit f = fit_whitened(whiten_columns(rest, x), y_rest);
  Eigen::VectorXd r(static_cast<Eigen::Index>(fold.size()));
  for (std::size_t k = 0; k < fold.size(); ++k) r(static_cast<Eigen::Index>(k)) = y(fold[k]) - x.row(fold[k]).dot(f.beta);
  return r;
}

}  // namespace

std::optional<SupportCheck> support_check(const ExplainInput& in, const Eigen::VectorXd& y, const NoiseModel& noise, const Eigen::MatrixXd& x_full,
                                          const Eigen::MatrixXd& x_minus, const Eigen::VectorXd& c, double sigma, const SupportCheckOptions& o) {
  const double peak = c.cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> support;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (!in.heldout[static_cast<std::size_t>(i)] && std::abs(c(i)) >= o.material * peak && peak > 0) support.push_back(i);
  }
  const auto folds = static_cast<std::size_t>(o.folds);
  if (support.size() < folds * static_cast<std::size_t>(o.min_fold_samples)) return std::nullopt;
  const auto training = static_cast<std::size_t>(in.training_size());
  if (training - support.size() / folds <= static_cast<std::size_t>(x_full.cols())) return std::nullopt;
  WhitenedGain gain;
  for (std::size_t k = 0; k < folds; ++k) {
    const std::vector<Eigen::Index> fold(support.begin() + static_cast<std::ptrdiff_t>(k * support.size() / folds),
                                         support.begin() + static_cast<std::ptrdiff_t>((k + 1) * support.size() / folds));
    std::vector<char> in_fold(static_cast<std::size_t>(in.size()), 0);
    for (Eigen::Index i : fold) in_fold[static_cast<std::size_t>(i)] = 1;
    std::vector<Eigen::Index> rest;
    rest.reserve(training);
    for (Eigen::Index i = 0; i < in.size(); ++i) {
      if (!in.heldout[static_cast<std::size_t>(i)] && !in_fold[static_cast<std::size_t>(i)]) rest.push_back(i);
    }
    const Whitener w_rest(noise, std::move(rest), in.signals.t_s), w_fold(noise, fold, in.signals.t_s);
    const Eigen::VectorXd y_rest = w_rest.apply(y);
    const Eigen::VectorXd r_full = fold_residual(x_full, y, w_rest, y_rest, fold), r_minus = fold_residual(x_minus, y, w_rest, y_rest, fold);
    // The fold's residuals placed on the recording's rows, whitened over the fold alone.
    Eigen::MatrixXd on_rows = Eigen::MatrixXd::Zero(in.size(), 2);
    for (std::size_t j = 0; j < fold.size(); ++j) on_rows.row(fold[j]) << r_full(static_cast<Eigen::Index>(j)), r_minus(static_cast<Eigen::Index>(j)) - r_full(static_cast<Eigen::Index>(j));
    const Eigen::MatrixXd white = w_fold.apply(on_rows);
    gain.add(white.col(0), white.col(1));
  }
  return SupportCheck{support.size(), in.signals.t_s[static_cast<std::size_t>(support.front())], in.signals.t_s[static_cast<std::size_t>(support.back())],
                      gain.testable(sigma), gain.z()};
}

}  // namespace gyrosid::explain
