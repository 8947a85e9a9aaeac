#include "explain/judge.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "explain/linear_fit.h"
#include "explain/refit.h"

namespace gyrosid::explain {
namespace {

Whitener rows_whitener(const ExplainInput& in, const NoiseModel& noise, const std::function<bool(Eigen::Index)>& keep) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (keep(i)) rows.push_back(i);
  }
  return Whitener(noise, rows, in.signals.t_s);
}

// Sum of squared residuals on the confirming held-out rows (unwhitened: a user's view of the fit).
double heldout_rss(const Eigen::VectorXd& residual, const ExplainInput& in) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (in.confirms(i)) s += residual(i) * residual(i);
  }
  return s;
}

std::vector<int> training_blocks(const ExplainInput& in) {
  std::vector<int> blocks;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    const int b = in.block[static_cast<std::size_t>(i)];
    if (!in.heldout[static_cast<std::size_t>(i)] && std::find(blocks.begin(), blocks.end(), b) == blocks.end()) blocks.push_back(b);
  }
  return blocks;
}

// Fraction of (up to eight) leave-one-training-block-out fits in which the effect keeps dBIC > 0.
double stability(const ExplainInput& in, const Eigen::VectorXd& y, const NoiseModel& noise, const Eigen::MatrixXd& x_full,
                 const Eigen::MatrixXd& x_minus, int extra_parameters) {
  int kept = 0, tried = 0;
  for (int b : training_blocks(in)) {
    if (tried == 8) break;
    const Whitener wb = rows_whitener(in, noise, [&](Eigen::Index i) {
      return !in.heldout[static_cast<std::size_t>(i)] && in.block[static_cast<std::size_t>(i)] != b;
    });
    const RowFit f1 = gls(x_full, y, wb), f0 = gls(x_minus, y, wb);
    const double n = static_cast<double>(f1.n);
    const int k = std::max(1, f1.rank - f0.rank) + extra_parameters;
    kept += n * std::log(f0.rss / f1.rss) - k * std::log(n) > 0;
    ++tried;
  }
  return tried ? static_cast<double>(kept) / tried : 1.0;
}

}  // namespace

RowFit gls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& w) {
  const WhitenedFit f = fit_whitened(w.apply(x), w.apply(y));
  return {f.beta, f.rss, static_cast<std::size_t>(f.residual.size()), f.rank};
}

std::vector<Judged> judge_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base, const SelectionResult& sel,
                                  const TermScaling& scaling, const Whitener& w) {
  const Eigen::MatrixXd x_full = model_columns(sel.model, in.signals, scaling);
  const RowFit fit_full = gls(x_full, y, w);
  const Eigen::VectorXd residual_full = y - x_full * fit_full.beta;
  const double sigma = std::sqrt(fit_full.rss / std::max<double>(1.0, static_cast<double>(fit_full.n) - fit_full.rank));
  std::size_t confirming = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) confirming += in.confirms(i);
  const std::optional<Whitener> heldout_w =
      confirming ? std::optional<Whitener>(rows_whitener(in, sel.noise, [&](Eigen::Index i) { return in.confirms(i); })) : std::nullopt;
  std::vector<Judged> out;
  std::size_t term = base.terms.size();
  const bool lag_selected = sel.model.lag_tau_s != base.lag_tau_s;
  std::optional<ProfiledFit> profiled_full;
  for (const auto& selected : sel.effects) {
    Judged j{selected, std::nullopt};
    const bool lag = selected.candidate.nonlinear == NonlinearParameter::coil_lag;
    // The selected model without this effect.
    ModelSpec minus = sel.model;
    if (lag) minus.lag_tau_s = base.lag_tau_s;
    else j.term = sel.model.terms[term], minus.terms.erase(minus.terms.begin() + static_cast<std::ptrdiff_t>(term++));
    const Eigen::MatrixXd x_minus = model_columns(minus, in.signals, scaling);
    const Eigen::VectorXd residual_minus = y - x_minus * gls(x_minus, y, w).beta;
    j.heldout_rss_without = heldout_rss(residual_minus, in);
    j.heldout_gain = j.heldout_rss_without - heldout_rss(residual_full, in);
    j.heldout_samples = confirming;
    if (heldout_w) {
      const Eigen::VectorXd r = heldout_w->apply(residual_full), d = heldout_w->apply(residual_minus - residual_full);
      const double sigma_h = std::sqrt(r.squaredNorm() / std::max<double>(1.0, static_cast<double>(r.size())));
      j.heldout_testable = d.norm() / std::sqrt(static_cast<double>(std::max<Eigen::Index>(1, d.size()))) > 0.05 * sigma;
      j.heldout_z = d.norm() > 0 ? (d.squaredNorm() + 2.0 * r.dot(d)) / (2.0 * sigma_h * d.norm()) : 0.0;
    }
    j.stability = stability(in, y, sel.noise, x_full, x_minus, lag ? 0 : selected.candidate.nonlinear_parameters());
    const ProfiledFit without = profiled_fit(in, y, minus, lag_selected && !lag, scaling, w);
    if (without.nonlinear > 0) {
      if (!profiled_full) profiled_full = profiled_fit(in, y, sel.model, lag_selected, scaling, w);
      const double n = static_cast<double>(fit_full.n);
      const int k = (j.term ? j.term->size() : 0) + selected.candidate.nonlinear_parameters();
      j.profiled_delta_bic = n * std::log(without.rss / std::min(profiled_full->rss, without.rss)) - k * std::log(n);
    }
    out.push_back(j);
  }
  return out;
}

}  // namespace gyrosid::explain
