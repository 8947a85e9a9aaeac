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

// The (up to eight) leave-one-training-block-out fits: each block's whitener and the selected model's
// residual sum of squares and rank there, computed once for every effect.
struct BlockFits {
  std::vector<Whitener> whiteners;
  std::vector<Eigen::VectorXd> y;  // whitened by each
  std::vector<RssAndRank> full;
};

BlockFits block_fits(const ExplainInput& in, const Eigen::VectorXd& y, const NoiseModel& noise, const Eigen::MatrixXd& x_full) {
  BlockFits b;
  for (int block : training_blocks(in)) {
    if (b.whiteners.size() == 8) break;
    b.whiteners.push_back(rows_whitener(in, noise, [&](Eigen::Index i) {
      return !in.heldout[static_cast<std::size_t>(i)] && in.block[static_cast<std::size_t>(i)] != block;
    }));
    b.y.push_back(b.whiteners.back().apply(y));
    b.full.push_back(whitened_rss_and_rank(b.whiteners.back().apply(x_full), b.y.back()));
  }
  return b;
}

// Fraction of the leave-one-training-block-out fits in which the effect keeps dBIC > 0.
double stability(const BlockFits& blocks, const Eigen::MatrixXd& x_minus, int extra_parameters) {
  int kept = 0;
  for (std::size_t k = 0; k < blocks.whiteners.size(); ++k) {
    const Whitener& wb = blocks.whiteners[k];
    const RssAndRank f1 = blocks.full[k], f0 = whitened_rss_and_rank(wb.apply(x_minus), blocks.y[k]);
    const double n = static_cast<double>(wb.rows().size());
    const int q = std::max(1, f1.rank - f0.rank) + extra_parameters;
    kept += n * std::log(f0.rss / f1.rss) - q * std::log(n) > 0;
  }
  return blocks.whiteners.empty() ? 1.0 : static_cast<double>(kept) / static_cast<double>(blocks.whiteners.size());
}

}  // namespace

RowFit gls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& w) {
  const WhitenedFit f = fit_whitened(w.apply(x), w.apply(y));
  return {f.beta, f.rss, static_cast<std::size_t>(f.residual.size()), f.rank};
}

Judgement judge_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base, const SelectionResult& sel,
                        const TermScaling& scaling, const Whitener& w) {
  const Eigen::MatrixXd x_full = model_columns(sel.model, in.signals, scaling);
  const RowFit fit_full = gls(x_full, y, w);
  const Eigen::VectorXd residual_full = y - x_full * fit_full.beta;
  const double sigma = std::sqrt(fit_full.rss / std::max<double>(1.0, static_cast<double>(fit_full.n) - fit_full.rank));
  std::size_t confirming = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) confirming += in.confirms(i);
  const std::optional<Whitener> heldout_w =
      confirming ? std::optional<Whitener>(rows_whitener(in, sel.noise, [&](Eigen::Index i) { return in.confirms(i); })) : std::nullopt;
  Judgement out;
  std::size_t term = base.terms.size();
  const bool lag_selected = sel.model.lag_tau_s != base.lag_tau_s;
  std::optional<ProfiledFit>& profiled_full = out.full;
  const BlockFits blocks = block_fits(in, y, sel.noise, x_full);
  for (const auto& selected : sel.effects) {
    Judged j{};
    j.effect = selected;
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
    j.stability = stability(blocks, x_minus, lag ? 0 : selected.candidate.nonlinear_parameters());
    const ProfiledFit without = profiled_fit(in, y, minus, lag_selected && !lag, scaling, w);
    j.profiled_without = without;
    if (without.nonlinear > 0) {
      if (!profiled_full) profiled_full = profiled_fit(in, y, sel.model, lag_selected, scaling, w);
      const double n = static_cast<double>(fit_full.n);
      const int k = (j.term ? j.term->size() : 0) + selected.candidate.nonlinear_parameters();
      j.profiled_delta_bic = n * std::log(without.rss / std::min(profiled_full->rss, without.rss)) - k * std::log(n);
    }
    out.effects.push_back(j);
  }
  return out;
}

}  // namespace gyrosid::explain
