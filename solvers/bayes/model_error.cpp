#include "solvers/bayes/model_error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "model/gaussian_node.h"

namespace gyrosid {
namespace {

constexpr int kMinLevels = 4;  // fewer levels: leaving one out removes too much of the input's range
// At most this many runs per fold: the null variance needs the runs' R x R covariance (32 MB at 2000), which a
// fast trajectory would otherwise make N / K on a side (every sample its own run).
constexpr std::size_t kMaxRuns = 2000;

// Fold index of every sample: the levels of the levelled input with the widest spacing, else time blocks.
std::vector<int> folds_of(const Eigen::MatrixXd& x, int blocks, int& count, std::string& kind) {
  const Eigen::Index n = x.rows();
  InputLevels best;
  Eigen::Index best_input = -1;
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    InputLevels l = input_levels(x.col(k));
    if (l.count >= kMinLevels && l.spacing > best.spacing) best = std::move(l), best_input = k;
  }
  if (best_input >= 0) {
    count = best.count, kind = str_cat("levels of input ", best_input);
    return best.level;
  }
  count = static_cast<int>(std::min<Eigen::Index>(blocks, n)), kind = "time blocks";
  std::vector<int> fold(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) fold[static_cast<std::size_t>(i)] = static_cast<int>(i * count / n);
  return fold;
}

// A fold's samples as groups over which the misfit is nearly constant while the noise averages down, as
// positions into the fold's rows (each group in time order), at most kMaxRuns groups:
//   runs:  consecutive samples over which the inputs move less than half a width;
//   cells: the samples in one cell of a grid of half a width per input, wherever in the fold they fall - a
//          trajectory that revisits its inputs (a rate cycle within a time block) puts many short runs in
//          one cell, whose mean has far less noise than any run's while the misfit, a function of the inputs,
//          is the same in all of them: the excess is resolved in fewer, less noisy groups.
std::vector<std::vector<std::size_t>> groups_of(const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& x,
                                                const Eigen::RowVectorXd& widths, ModelErrorGroups kind) {
  std::vector<std::vector<std::size_t>> groups;
  if (kind == ModelErrorGroups::runs) {
    std::size_t b = 0;
    while (b < rows.size()) {
      std::size_t end = b + 1;
      while (end < rows.size() && rows[end] == rows[end - 1] + 1 &&
             ((x.row(rows[end]) - x.row(rows[b])).cwiseAbs().array() <= 0.5 * widths.array()).all()) {
        ++end;
      }
      groups.emplace_back();
      for (std::size_t i = b; i < end; ++i) groups.back().push_back(i);
      b = end;
    }
  } else {
    std::map<std::vector<long>, std::vector<std::size_t>> cells;  // ordered by cell: neighbours stay near for the merge below
    std::vector<long> key(static_cast<std::size_t>(x.cols()));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (Eigen::Index k = 0; k < x.cols(); ++k) key[static_cast<std::size_t>(k)] = static_cast<long>(std::floor(x(rows[i], k) / (0.5 * widths(k))));
      cells[key].push_back(i);
    }
    for (auto& [cell, members] : cells) groups.push_back(std::move(members));
  }
  if (groups.size() <= kMaxRuns) return groups;
  // Too many: neighbouring groups become one (their mean averages some misfit away - a weaker test, still a
  // valid one, as the null covariance is that of the same groups).
  const std::size_t merge = (groups.size() + kMaxRuns - 1) / kMaxRuns;
  std::vector<std::vector<std::size_t>> merged;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    if (i % merge == 0) merged.emplace_back();
    merged.back().insert(merged.back().end(), groups[i].begin(), groups[i].end());
  }
  for (auto& g : merged) std::sort(g.begin(), g.end());
  return merged;
}

struct FoldExcess {
  double value = 0.0;
  double null_variance = 0.0;  // the variance of `value` were the model class right
  bool valid = false;
};

// The weighted mean excess e_r^2 - c_rr over the groups of one fold (model_error.h), c_rr the group mean's
// variance were the model class right: the estimate's h_r' A_k^-1 h_r plus the noise's. Its variance under
// that hypothesis, from the group means' joint covariance C = H A_k^-1 H' + V (Gaussian: cov(e_r^2, e_s^2) =
// 2 c_rs^2), is 2 sum_rs w_r w_s c_rs^2 / (sum w)^2. (The spread of the excess over folds is no measure of
// its null variance: a real misfit differs from fold to fold, e.g. a ripple that grows with the rate.)
FoldExcess fold_excess(const std::vector<Eigen::Index>& rows, const Eigen::VectorXd& e, const Eigen::MatrixXd& h,
                       const Eigen::LLT<Eigen::MatrixXd>& a, const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths,
                       const NoiseModel& noise, const std::vector<double>& t_s, ModelErrorGroups kind) {
  const auto groups = groups_of(rows, x, widths, kind);
  const Eigen::Index nr = static_cast<Eigen::Index>(groups.size());
  if (nr == 0) return {};
  Eigen::MatrixXd hbar = Eigen::MatrixXd::Zero(nr, h.cols());
  Eigen::VectorXd ebar = Eigen::VectorXd::Zero(nr);
  std::vector<std::vector<double>> group_times(groups.size());
  for (Eigen::Index r = 0; r < nr; ++r) {
    const auto& g = groups[static_cast<std::size_t>(r)];
    for (const std::size_t i : g) {
      hbar.row(r) += h.row(static_cast<Eigen::Index>(i)), ebar(r) += e(static_cast<Eigen::Index>(i));
      group_times[static_cast<std::size_t>(r)].push_back(t_s[static_cast<std::size_t>(rows[i])]);
    }
    hbar.row(r) /= static_cast<double>(g.size()), ebar(r) /= static_cast<double>(g.size());
  }
  const Eigen::MatrixXd g = a.matrixL().solve(hbar.transpose());  // (M+P) x R: C_estimate = g' g
  Eigen::MatrixXd c = g.transpose() * g;
  c += group_mean_noise_covariance(group_times, noise);
  const Eigen::VectorXd w = c.diagonal().array().square().inverse().matrix();
  const double sw = w.sum();
  FoldExcess out;
  out.value = w.dot((ebar.array().square() - c.diagonal().array()).matrix()) / sw;
  out.null_variance = 2.0 * w.dot(c.array().square().matrix() * w) / (sw * sw);
  out.valid = sw > 0 && std::isfinite(out.value);
  return out;
}

// The fit's regressors [rbf, fixed] (the order of fit.covariance) and its noise model in y units; with white
// noise also the whitened Gram matrix and right-hand side of all samples once, from which each fold's rows
// are subtracted.
struct CvSystem {
  Eigen::MatrixXd h, hw, gram;
  Eigen::VectorXd yw, b;
  NoiseModel noise;
  bool coloured = false;

  CvSystem(const BayesProblem& p, const BayesFit& fit, const std::vector<double>& t_s) : coloured(fit.noise.has_value()) {
    const Eigen::Index m = fit.centres.rows(), q = p.fixed.cols();
    h.resize(p.y.size(), m + q);
    if (m > 0) h.leftCols(m) = gaussian_columns(p.x, fit.centres, fit.widths);
    h.rightCols(q) = p.fixed;
    noise.dt_s = median_sample_interval(t_s);
    noise.white_var = std::exp(-fit.log_beta);
    if (coloured) {
      noise = *fit.noise;
      return;
    }
    const double root_beta = std::exp(0.5 * fit.log_beta);
    hw = root_beta * h;
    yw = root_beta * p.y;
    gram = hw.transpose() * hw;
    b = hw.transpose() * yw;
  }

  // The whitened normal equations a x = bk of the fit without fold k (whose rows are `rows`).
  void without_fold(const Eigen::VectorXd& y, const std::vector<int>& fold, int k, const std::vector<Eigen::Index>& rows,
                    const std::vector<double>& t_s, Eigen::MatrixXd& a, Eigen::VectorXd& bk) const {
    if (coloured) {
      // The other samples whitened anew (the filter runs across the gap). Dropping the fold's rows of the full
      // whitening instead would leave the fold's information in the innovations after it, and strip a block at
      // the start of the record of the level the constant is known by.
      std::vector<Eigen::Index> train;
      for (Eigen::Index i = 0; i < y.size(); ++i)
        if (fold[static_cast<std::size_t>(i)] != k) train.push_back(i);
      const Whitener w(noise, train, t_s, RandomWalkStart::zero);
      const Eigen::MatrixXd hwt = w.apply(h);
      a = hwt.transpose() * hwt, bk = hwt.transpose() * w.apply(y);
      return;
    }
    Eigen::MatrixXd hwk(static_cast<Eigen::Index>(rows.size()), h.cols());
    Eigen::VectorXd ywk(hwk.rows());
    for (std::size_t r = 0; r < rows.size(); ++r) hwk.row(static_cast<Eigen::Index>(r)) = hw.row(rows[r]), ywk(static_cast<Eigen::Index>(r)) = yw(rows[r]);
    a = gram, bk = b - hwk.transpose() * ywk;
    a.noalias() -= hwk.transpose() * hwk;
  }
};

}  // namespace

Eigen::MatrixXd group_mean_noise_covariance(const std::vector<std::vector<double>>& groups, const NoiseModel& m) {
  const Eigen::Index nr = static_cast<Eigen::Index>(groups.size());
  Eigen::VectorXd n(nr);
  for (Eigen::Index r = 0; r < nr; ++r) n(r) = static_cast<double>(groups[static_cast<std::size_t>(r)].size());
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(nr, nr);
  if (m.gm_var > 0) {
    // One sweep over every sample in time order: acc(s) = sum over the earlier samples j of group s of
    // exp(-(t - t_j)/tau), decayed from sample to sample; sample i of group r adds acc to row r of the pair
    // sums (pairs j < i). The full double sum is pairs + pairs' + n on the diagonal (i = j).
    std::vector<std::pair<double, Eigen::Index>> order;
    for (Eigen::Index r = 0; r < nr; ++r)
      for (const double t : groups[static_cast<std::size_t>(r)]) order.emplace_back(t, r);
    std::sort(order.begin(), order.end());
    Eigen::VectorXd acc = Eigen::VectorXd::Zero(nr);
    Eigen::MatrixXd pairs = Eigen::MatrixXd::Zero(nr, nr);
    for (std::size_t i = 0; i < order.size(); ++i) {
      if (i > 0) acc *= std::exp(-(order[i].first - order[i - 1].first) / m.gm_tau_s);
      pairs.row(order[i].second) += acc.transpose();
      acc(order[i].second) += 1.0;
    }
    v = m.gm_var * (pairs + pairs.transpose());
    v.diagonal() += m.gm_var * n;
  }
  v.diagonal() += m.white_var * n;
  return (v.array() / (n * n.transpose()).array()).matrix();
}

std::string ModelErrorEstimate::describe(double to_dph) const {
  const auto dph = [&](double v) { return format_significant(std::sqrt(std::max(0.0, v)) * to_dph, 3); };
  if (folds == 0) return "model error: not estimated";
  return str_cat("model error by cross-validation over ", folds, " ", fold_kind, ": ",
                 variance > 0 ? str_cat(dph(variance), " deg/h added to the predictive sigma (excess ", format_significant(mean_excess * to_dph * to_dph, 3), " +- ", format_significant(standard_error * to_dph * to_dph, 3), " (deg/h)^2)")
                              : str_cat("none (excess ", format_significant(mean_excess * to_dph * to_dph, 3), " +- ",
                                        format_significant(standard_error * to_dph * to_dph, 3), " (deg/h)^2)"));
}

ModelErrorEstimate model_error_by_cv(const BayesProblem& p, const BayesFit& fit, const std::vector<double>& t_s, const ModelErrorOptions& o) {
  ModelErrorEstimate out;
  const Eigen::Index n = p.y.size(), m = fit.centres.rows(), q = p.fixed.cols();
  if (static_cast<Eigen::Index>(t_s.size()) != n) fail("model error: ", t_s.size(), " sample times for ", n, " samples");
  const CvSystem system(p, fit, t_s);
  const Eigen::MatrixXd& h = system.h;
  const NoiseModel& noise = system.noise;
  // Prior precision: alpha on the RBF weights, a vanishing one on the flat-prior fixed columns (a fold may
  // remove the support of one of them).
  Eigen::VectorXd prior(m + q);
  prior.head(m).setConstant(std::exp(fit.log_alpha));
  prior.tail(q).setConstant(1e-10);  // targets have unit RMS, so the data's precision is far above it

  const std::vector<int> fold = folds_of(p.x, o.blocks, out.folds, out.fold_kind);
  const bool level_folds = out.fold_kind != "time blocks";
  std::vector<double> excess;
  double null_variance = 0.0, squared_residuals = 0.0;
  Eigen::Index predicted = 0;
  for (int k = 0; k < out.folds; ++k) {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index i = 0; i < n; ++i)
      if (fold[static_cast<std::size_t>(i)] == k) rows.push_back(i);
    if (rows.empty() || static_cast<Eigen::Index>(rows.size()) == n) continue;
    Eigen::MatrixXd a;
    Eigen::VectorXd bk;
    system.without_fold(p.y, fold, k, rows, t_s, a, bk);
    a.diagonal() += prior;
    const Eigen::LLT<Eigen::MatrixXd> llt(a);
    if (llt.info() != Eigen::Success) continue;
    const Eigen::VectorXd mean = llt.solve(bk);
    Eigen::MatrixXd hk(static_cast<Eigen::Index>(rows.size()), m + q);
    Eigen::VectorXd ek(hk.rows());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      hk.row(static_cast<Eigen::Index>(r)) = h.row(rows[r]);
      ek(static_cast<Eigen::Index>(r)) = p.y(rows[r]) - h.row(rows[r]).dot(mean);
    }
    squared_residuals += ek.squaredNorm(), predicted += ek.size();
    const FoldExcess f = fold_excess(rows, ek, hk, llt, p.x, fit.widths, noise, t_s, o.groups);
    if (f.valid) excess.push_back(f.value), null_variance += f.null_variance;
  }
  if (predicted > 0) out.cv_mse = squared_residuals / static_cast<double>(predicted);
  if (excess.size() < 2) return out;
  const double k = static_cast<double>(excess.size());
  double mean = 0.0;
  for (const double v : excess) mean += v / k;
  out.mean_excess = mean;
  out.standard_error = std::sqrt(null_variance) / k;  // folds taken as independent
  // A left-out level is predicted at one level spacing from the nearest level kept; between levels a point is
  // at most half a spacing from one. The misfit's variance at half the distance is taken as a quarter: its
  // rms grows linearly with the distance (a smooth misfit grows faster near the data, so this errs large).
  out.reach = level_folds ? 0.25 : 1.0;
  // The estimate itself, never negative - not kept only when significant: a misfit of 1.3 standard errors
  // (sensor C's sine sweep at 1 deg/h: 0.0255 +- 0.0196 (deg/h)^2) still costs the band 7 points of
  // coverage (0.876), and under the null this adds 0.4 standard errors on average.
  out.variance = out.reach * std::max(0.0, mean);
  return out;
}

}  // namespace gyrosid
