#include "explain/judge.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "core/bounded_search.h"
#include "explain/linear_fit.h"
#include "explain/noise_likelihood.h"
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
double heldout_rss(const Eigen::VectorXd& residual, const ExplainInput& in, const std::vector<char>& outside) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (in.confirms(i, outside)) s += residual(i) * residual(i);
  }
  return s;
}

// The held-out test of one effect: the selected model (residual_full) against it without the effect
// (residual_minus), both scored on the held-out rows inside the training support of the baseline and of
// both models (`outside`, heldout_support.h). `sigma`: the training fit's noise level.
void heldout_test(const ExplainInput& in, const NoiseModel& noise, const std::vector<char>& outside, const Eigen::VectorXd& residual_full,
                  const Eigen::VectorXd& residual_minus, double sigma, Judged& j) {
  j.heldout_rss_without = heldout_rss(residual_minus, in, outside);
  j.heldout_gain = j.heldout_rss_without - heldout_rss(residual_full, in, outside);
  j.heldout_samples = 0;
  for (Eigen::Index i = 0; i < in.size(); ++i) j.heldout_samples += in.confirms(i, outside);
  if (j.heldout_samples == 0) return;
  const Whitener heldout_w = rows_whitener(in, noise, [&](Eigen::Index i) { return in.confirms(i, outside); });
  WhitenedGain gain;
  gain.add(heldout_w.apply(residual_full), heldout_w.apply(residual_minus - residual_full));
  j.heldout_testable = gain.testable(sigma);
  j.heldout_z = gain.z();
}

// The effect's own contribution X_e beta_e (deg/h, every sample): its columns in the selected model's, from
// the first column of its term `term`.
Eigen::VectorXd contribution(const ModelSpec& model, std::size_t term, const Eigen::MatrixXd& x_full, const Eigen::VectorXd& beta) {
  Eigen::Index at = 0;
  for (std::size_t k = 0; k < term; ++k) at += model.terms[k].size();
  const Eigen::Index size = model.terms[term].size();
  return x_full.middleCols(at, size) * beta.segment(at, size);
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
    b.full.push_back(whitened_rss_and_rank(whiten_columns(b.whiteners.back(), x_full), b.y.back()));
  }
  return b;
}

// Fraction of the leave-one-training-block-out fits in which the effect keeps dBIC > 0.
double stability(const BlockFits& blocks, const Eigen::MatrixXd& x_minus, int extra_parameters) {
  int kept = 0;
  for (std::size_t k = 0; k < blocks.whiteners.size(); ++k) {
    const Whitener& wb = blocks.whiteners[k];
    const RssAndRank f1 = blocks.full[k], f0 = whitened_rss_and_rank(whiten_columns(wb, x_minus), blocks.y[k]);
    const double n = static_cast<double>(wb.rows().size());
    const int q = std::max(1, f1.rank - f0.rank) + extra_parameters;
    kept += n * std::log(f0.rss / f1.rss) - q * std::log(n) > 0;
  }
  return blocks.whiteners.empty() ? 1.0 : static_cast<double>(kept) / static_cast<double>(blocks.whiteners.size());
}

// The selected model with `removed` (a term index) taken out and `further` (a further component of the
// effect whose term is `first`) put in, both components' time constants re-optimised together within the
// further component's grid (the effect's own range) by BOBYQA over their logarithms, every linear coefficient
// solved inside: its whitened RSS and the two time constants.
struct FurtherFit {
  double rss = 0.0, tau = 0.0, first_tau = 0.0;
};
FurtherFit fit_with_further(const ExplainInput& in, const Eigen::VectorXd& yw, const ModelSpec& model, std::size_t removed, std::size_t first,
                            const Candidate& further, const TermScaling& sc, const Whitener& w) {
  ModelSpec alt = model;
  alt.terms.erase(alt.terms.begin() + static_cast<std::ptrdiff_t>(removed));
  const std::size_t f = first > removed ? first - 1 : first;
  alt.terms.push_back(further.term->with_parameter(further.tau_grid_s.front()));
  const auto rss = [&](double log_first, double log_tau) {
    ModelSpec m = alt;
    m.terms[f] = m.terms[f].with_parameter(std::exp(log_first));
    m.terms.back() = m.terms.back().with_parameter(std::exp(log_tau));
    return whitened_rss(whiten_columns(w, model_columns(m, in.signals, sc)), yw);
  };
  const double first0 = std::log(model.terms[first].parameter()->value);
  // The second time constant started at the best of its grid (the first held), then both refined.
  double start = std::log(further.tau_grid_s.front()), best = std::numeric_limits<double>::infinity();
  for (double tau : further.tau_grid_s) {
    const double r = rss(first0, std::log(tau));
    if (r < best) best = r, start = std::log(tau);
  }
  const double lo = std::log(further.tau_grid_s.front()), hi = std::log(further.tau_grid_s.back());
  BoundedSearchOptions bobyqa;
  bobyqa.xtol_abs = 1e-2;  // tau to 1 %
  bobyqa.max_evaluations = 60;
  const BoundedSearchResult r = minimize_bounded([&](const std::vector<double>& v) { return rss(v[0], v[1]); },
                                                 {std::clamp(first0, lo, hi), start}, {lo, lo}, {hi, hi}, bobyqa);
  if (r.value < best) return {r.value, std::exp(r.x[1]), std::exp(r.x[0])};
  return {best, std::exp(start), std::exp(first0)};
}

}  // namespace

RowFit gls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& w) {
  const WhitenedFit f = fit_whitened(w.apply(x), w.apply(y));
  return {f.beta, f.rss, static_cast<std::size_t>(f.residual.size()), f.rank};
}

Judgement judge_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base, const SelectionResult& sel,
                        const TermScaling& scaling, const Whitener& w, HeldoutSupport& support, const std::vector<Candidate>& candidates,
                        const SupportCheckOptions& support_options) {
  const Eigen::MatrixXd x_full = model_columns(sel.model, in.signals, scaling);
  const RowFit fit_full = gls(x_full, y, w);
  const Eigen::VectorXd residual_full = y - x_full * fit_full.beta;
  const double sigma = std::sqrt(fit_full.rss / std::max<double>(1.0, static_cast<double>(fit_full.n) - fit_full.rank));
  Judgement out;
  std::size_t term = base.terms.size();
  const bool lag_selected = sel.model.lag_tau_s != base.lag_tau_s;
  std::optional<ProfiledFit>& profiled_full = out.full;
  const BlockFits blocks = block_fits(in, y, sel.noise, x_full);
  // Effects with a further component (a warm-up's second time constant) and their term in the selected model.
  struct Rival {
    const Candidate* further;
    std::size_t term;
    std::string id;
  };
  std::vector<Rival> rivals;
  std::optional<Eigen::VectorXd> yw;
  for (const auto& selected : sel.effects) {
    Judged j{};
    j.effect = selected;
    const bool lag = selected.candidate.nonlinear == NonlinearParameter::coil_lag;
    // The selected model without this effect.
    ModelSpec minus = sel.model;
    if (lag) minus.lag_tau_s = base.lag_tau_s;
    const std::size_t this_term = term;
    if (!lag) j.term = sel.model.terms[term], minus.terms.erase(minus.terms.begin() + static_cast<std::ptrdiff_t>(term++));
    if (!lag && selected.candidate.effect->is_physics()) {
      for (const Rival& r : rivals) {
        if (!yw) yw = w.apply(y);
        const FurtherFit f = fit_with_further(in, *yw, sel.model, this_term, r.term, *r.further, scaling, w);
        const double n = static_cast<double>(fit_full.n);
        const int k = j.term->size() + selected.nonlinear_parameters() - (r.further->term->size() + 1);
        const FurtherComponent c{r.id, f.tau, f.first_tau, n * std::log(f.rss / fit_full.rss) - k * std::log(n)};
        if (!j.further || c.delta_bic < j.further->delta_bic) j.further = c;
      }
      for (const Candidate& c : candidates) {
        if (c.further_component && c.effect == selected.candidate.effect) rivals.push_back({&c, this_term, std::string(c.id())});
      }
    }
    const Eigen::MatrixXd x_minus = model_columns(minus, in.signals, scaling);
    const Eigen::VectorXd residual_minus = y - x_minus * gls(x_minus, y, w).beta;
    const std::vector<char> outside = support.outside({&sel.model, &minus});
    heldout_test(in, sel.noise, outside, residual_full, residual_minus, sigma, j);
    if (!lag) {
      const Eigen::VectorXd c = contribution(sel.model, this_term, x_full, fit_full.beta);
      j.heldout_holds = heldout_blocks_hold(in, outside, c, support_options.held_share);
      if (!j.heldout_holds) j.support = support_check(in, y, sel.noise, x_full, x_minus, c, sigma, support_options);
    }
    j.stability = stability(blocks, x_minus, lag ? 0 : selected.nonlinear_parameters());
    const ProfiledFit without = profiled_fit(in, y, minus, lag_selected && !lag, scaling, w);
    j.profiled_without = without;
    if (without.nonlinear > 0) {
      if (!profiled_full) profiled_full = profiled_fit(in, y, sel.model, lag_selected, scaling, w);
      const double n = static_cast<double>(fit_full.n);
      const int k = (j.term ? j.term->size() : 0) + selected.nonlinear_parameters();
      j.profiled_delta_bic = n * std::log(without.rss / std::min(profiled_full->rss, without.rss)) - k * std::log(n);
    }
    out.effects.push_back(j);
  }
  return out;
}

}  // namespace gyrosid::explain
