#include "solvers/bayes/model_error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "model/gaussian_node.h"

namespace gyrosid {
namespace {

constexpr int kTimeBlocks = 10;
constexpr int kMinLevels = 4;  // fewer levels: leaving one out removes too much of the input's range
// At most this many runs per fold: the null variance needs the runs' R x R covariance (32 MB at 2000), which a
// fast trajectory would otherwise make N / K on a side (every sample its own run).
constexpr std::size_t kMaxRuns = 2000;

// Fold index of every sample: the levels of the levelled input with the widest spacing, else time blocks.
std::vector<int> folds_of(const Eigen::MatrixXd& x, int& count, std::string& kind) {
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
  count = static_cast<int>(std::min<Eigen::Index>(kTimeBlocks, n)), kind = "time blocks";
  std::vector<int> fold(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) fold[static_cast<std::size_t>(i)] = static_cast<int>(i * count / n);
  return fold;
}

// The runs of one fold: consecutive samples over which the inputs move less than half a width (the misfit is
// nearly constant over a run while the noise averages down), as [begin, end) into the fold's rows; at most
// kMaxRuns.
std::vector<std::pair<std::size_t, std::size_t>> runs_of(const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& x,
                                                         const Eigen::RowVectorXd& widths) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  std::size_t b = 0;
  while (b < rows.size()) {
    std::size_t end = b + 1;
    while (end < rows.size() && rows[end] == rows[end - 1] + 1 &&
           ((x.row(rows[end]) - x.row(rows[b])).cwiseAbs().array() <= 0.5 * widths.array()).all()) {
      ++end;
    }
    runs.emplace_back(b, end);
    b = end;
  }
  if (runs.size() <= kMaxRuns) return runs;
  // Too many: groups of consecutive runs become one (their mean averages some misfit away - a weaker test,
  // still a valid one, as the null covariance is that of the same groups).
  const std::size_t group = (runs.size() + kMaxRuns - 1) / kMaxRuns;
  std::vector<std::pair<std::size_t, std::size_t>> merged;
  for (std::size_t i = 0; i < runs.size(); i += group) merged.emplace_back(runs[i].first, runs[std::min(i + group, runs.size()) - 1].second);
  return merged;
}

struct FoldExcess {
  double value = 0.0;
  double null_variance = 0.0;  // the variance of `value` were the model class right
  bool valid = false;
};

// The weighted mean excess e_r^2 - c_rr over the runs of one fold (model_error.h), c_rr the run mean's
// variance were the model class right: the estimate's h_r' A_k^-1 h_r plus the noise's. Its variance under
// that hypothesis, from the run means' joint covariance C = H A_k^-1 H' + V (Gaussian: cov(e_r^2, e_s^2) =
// 2 c_rs^2), is 2 sum_rs w_r w_s c_rs^2 / (sum w)^2. (The spread of the excess over folds is no measure of
// its null variance: a real misfit differs from fold to fold, e.g. a ripple that grows with the rate.)
FoldExcess fold_excess(const std::vector<Eigen::Index>& rows, const Eigen::VectorXd& e, const Eigen::MatrixXd& h,
                       const Eigen::LLT<Eigen::MatrixXd>& a, const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths,
                       const NoiseModel& noise, const std::vector<double>& t_s) {
  const auto runs = runs_of(rows, x, widths);
  const Eigen::Index nr = static_cast<Eigen::Index>(runs.size());
  if (nr == 0) return {};
  Eigen::MatrixXd hbar(nr, h.cols());
  Eigen::VectorXd ebar(nr);
  for (Eigen::Index r = 0; r < nr; ++r) {
    const auto [b, end] = runs[static_cast<std::size_t>(r)];
    const Eigen::Index len = static_cast<Eigen::Index>(end - b);
    hbar.row(r) = h.middleRows(static_cast<Eigen::Index>(b), len).colwise().sum() / static_cast<double>(len);
    ebar(r) = e.segment(static_cast<Eigen::Index>(b), len).sum() / static_cast<double>(len);
  }
  const Eigen::MatrixXd g = a.matrixL().solve(hbar.transpose());  // (M+P) x R: C_estimate = g' g
  Eigen::MatrixXd c = g.transpose() * g;
  std::vector<std::vector<double>> run_times;
  for (const auto& [b, end] : runs) {
    run_times.emplace_back();
    for (std::size_t i = b; i < end; ++i) run_times.back().push_back(t_s[static_cast<std::size_t>(rows[i])]);
  }
  c += run_mean_noise_covariance(run_times, noise);
  const Eigen::VectorXd w = c.diagonal().array().square().inverse().matrix();
  const double sw = w.sum();
  FoldExcess out;
  out.value = w.dot((ebar.array().square() - c.diagonal().array()).matrix()) / sw;
  out.null_variance = 2.0 * w.dot(c.array().square().matrix() * w) / (sw * sw);
  out.valid = sw > 0 && std::isfinite(out.value);
  return out;
}

}  // namespace

Eigen::MatrixXd run_mean_noise_covariance(const std::vector<std::vector<double>>& runs, const NoiseModel& m) {
  const Eigen::Index nr = static_cast<Eigen::Index>(runs.size());
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(nr, nr);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(nr), b = Eigen::VectorXd::Zero(nr);
  for (Eigen::Index r = 0; r < nr; ++r) {
    const std::vector<double>& t = runs[static_cast<std::size_t>(r)];
    const double n = static_cast<double>(t.size());
    double within = n * (m.white_var + m.gm_var);
    if (m.gm_var > 0) {
      // sum_{j<i} exp(-(t_i - t_j)/tau) = sum_i s_i with s_i = exp(-(t_i - t_{i-1})/tau) (s_{i-1} + 1), s_0 = 0.
      double s = 0.0, pairs = 0.0;
      for (std::size_t i = 0; i < t.size(); ++i) {
        a(r) += std::exp(-(t.back() - t[i]) / m.gm_tau_s), b(r) += std::exp(-(t[i] - t.front()) / m.gm_tau_s);
        if (i > 0) s = std::exp(-(t[i] - t[i - 1]) / m.gm_tau_s) * (s + 1.0), pairs += s;
      }
      within += 2.0 * m.gm_var * pairs;
    }
    v(r, r) = within / (n * n);
  }
  if (!(m.gm_var > 0)) return v;
  for (Eigen::Index r = 0; r < nr; ++r)
    for (Eigen::Index s = r + 1; s < nr; ++s) {
      const auto& tr = runs[static_cast<std::size_t>(r)];
      const auto& ts = runs[static_cast<std::size_t>(s)];
      const double gap = ts.front() - tr.back();
      if (gap > 40.0 * m.gm_tau_s) break;  // runs are in time order: every later one is farther
      v(r, s) = v(s, r) = m.gm_var * a(r) * std::exp(-gap / m.gm_tau_s) * b(s) / (static_cast<double>(tr.size()) * static_cast<double>(ts.size()));
    }
  return v;
}

std::string ModelErrorEstimate::describe(double to_dph) const {
  const auto dph = [&](double v) { return format_significant(std::sqrt(std::max(0.0, v)) * to_dph, 3); };
  if (folds == 0) return "model error: not estimated";
  return str_cat("model error by cross-validation over ", folds, " ", fold_kind, ": ",
                 variance > 0 ? str_cat(dph(variance), " deg/h added to the predictive sigma")
                              : str_cat("none significant (excess ", format_significant(mean_excess * to_dph * to_dph, 3), " +- ",
                                        format_significant(standard_error * to_dph * to_dph, 3), " (deg/h)^2)"));
}

ModelErrorEstimate model_error_by_cv(const BayesProblem& p, const BayesFit& fit, const std::vector<double>& t_s) {
  ModelErrorEstimate out;
  const Eigen::Index n = p.y.size(), m = fit.centres.rows(), q = p.fixed.cols();
  if (static_cast<Eigen::Index>(t_s.size()) != n) fail("model error: ", t_s.size(), " sample times for ", n, " samples");
  // Regressors [rbf, fixed] (the order of fit.covariance) and the noise model in y units.
  Eigen::MatrixXd h(n, m + q);
  if (m > 0) h.leftCols(m) = gaussian_columns(p.x, fit.centres, fit.widths);
  h.rightCols(q) = p.fixed;
  NoiseModel noise;
  noise.dt_s = median_sample_interval(t_s);
  noise.white_var = std::exp(-fit.log_beta);
  if (fit.noise) noise = *fit.noise;
  // White noise: the full Gram matrix once, each fold's subtracted (coloured: per fold, below).
  const double root_beta = std::exp(0.5 * fit.log_beta);
  const Eigen::MatrixXd hw = fit.noise ? Eigen::MatrixXd() : Eigen::MatrixXd(root_beta * h);
  const Eigen::VectorXd yw = fit.noise ? Eigen::VectorXd() : Eigen::VectorXd(root_beta * p.y);
  const Eigen::MatrixXd gram = fit.noise ? Eigen::MatrixXd() : Eigen::MatrixXd(hw.transpose() * hw);
  const Eigen::VectorXd b = fit.noise ? Eigen::VectorXd() : Eigen::VectorXd(hw.transpose() * yw);
  // Prior precision: alpha on the RBF weights, a vanishing one on the flat-prior fixed columns (a fold may
  // remove the support of one of them).
  Eigen::VectorXd prior(m + q);
  prior.head(m).setConstant(std::exp(fit.log_alpha));
  prior.tail(q).setConstant(1e-10);  // targets have unit RMS, so the data's precision is far above it

  const std::vector<int> fold = folds_of(p.x, out.folds, out.fold_kind);
  const bool level_folds = out.fold_kind != "time blocks";
  std::vector<double> excess;
  double null_variance = 0.0;
  for (int k = 0; k < out.folds; ++k) {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index i = 0; i < n; ++i)
      if (fold[static_cast<std::size_t>(i)] == k) rows.push_back(i);
    if (rows.empty() || static_cast<Eigen::Index>(rows.size()) == n) continue;
    Eigen::MatrixXd a;
    Eigen::VectorXd bk;
    if (fit.noise) {
      // Coloured: the other samples whitened anew (the filter runs across the gap). Dropping the fold's rows
      // of the full whitening instead would leave the fold's information in the innovations after it, and
      // strip a block at the start of the record of the level the constant is known by.
      std::vector<Eigen::Index> train;
      for (Eigen::Index i = 0; i < n; ++i)
        if (fold[static_cast<std::size_t>(i)] != k) train.push_back(i);
      const Whitener w(noise, train, t_s, RandomWalkStart::zero);
      const Eigen::MatrixXd hwt = w.apply(h);
      a = hwt.transpose() * hwt, bk = hwt.transpose() * w.apply(p.y);
    } else {
      Eigen::MatrixXd hwk(static_cast<Eigen::Index>(rows.size()), m + q);
      Eigen::VectorXd ywk(hwk.rows());
      for (std::size_t r = 0; r < rows.size(); ++r) hwk.row(static_cast<Eigen::Index>(r)) = hw.row(rows[r]), ywk(static_cast<Eigen::Index>(r)) = yw(rows[r]);
      a = gram, bk = b - hwk.transpose() * ywk;
      a.noalias() -= hwk.transpose() * hwk;
    }
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
    const FoldExcess f = fold_excess(rows, ek, hk, llt, p.x, fit.widths, noise, t_s);
    if (f.valid) excess.push_back(f.value), null_variance += f.null_variance;
  }
  if (excess.size() < 2) return out;
  const double k = static_cast<double>(excess.size());
  double mean = 0.0;
  for (const double v : excess) mean += v / k;
  out.mean_excess = mean;
  out.standard_error = std::sqrt(null_variance) / k;  // folds taken as independent
  // A left-out level is predicted at one level spacing from the nearest level kept; between levels a point is
  // at most half a spacing from one. The misfit's variance at half the distance is taken as a quarter: its
  // rms grows linearly with the distance (a smooth misfit grows faster near the data, so this errs large).
  const double reach = level_folds ? 0.25 : 1.0;
  out.variance = mean > 2.0 * out.standard_error ? reach * mean : 0.0;
  return out;
}

}  // namespace gyrosid
