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

// Variance of the mean of the noise over samples rows[b..e) (white + Gauss-Markov, y units^2).
double run_noise_variance(const std::vector<Eigen::Index>& rows, std::size_t b, std::size_t e, const NoiseModel& m,
                          const std::vector<double>& t_s) {
  const double n = static_cast<double>(e - b);
  double sum = n * (m.white_var + m.gm_var);
  if (m.gm_var > 0) {
    for (std::size_t i = b; i < e; ++i)
      for (std::size_t j = b; j < i; ++j) {
        const double dt = t_s[static_cast<std::size_t>(rows[i])] - t_s[static_cast<std::size_t>(rows[j])];
        sum += 2.0 * m.gm_var * std::exp(-std::abs(dt) / m.gm_tau_s);
      }
  }
  return sum / (n * n);
}

struct FoldExcess {
  double value = 0.0;
  bool valid = false;
};

// The weighted mean excess e_r^2 - a_r - v_r over the runs of one fold (model_error.h).
FoldExcess fold_excess(const std::vector<Eigen::Index>& rows, const Eigen::VectorXd& e, const Eigen::MatrixXd& h,
                       const Eigen::LLT<Eigen::MatrixXd>& a, const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths,
                       const NoiseModel& noise, const std::vector<double>& t_s) {
  double num = 0.0, den = 0.0;
  std::size_t b = 0;
  while (b < rows.size()) {
    std::size_t end = b + 1;
    while (end < rows.size() && rows[end] == rows[end - 1] + 1 &&
           ((x.row(rows[end]) - x.row(rows[b])).cwiseAbs().array() <= 0.5 * widths.array()).all()) {
      ++end;
    }
    const double n = static_cast<double>(end - b);
    const Eigen::VectorXd hbar = h.middleRows(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(end - b)).colwise().sum().transpose() / n;
    const double ebar = e.segment(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(end - b)).sum() / n;
    const double var_estimate = hbar.dot(a.solve(hbar));
    const double var_noise = run_noise_variance(rows, b, end, noise, t_s);
    const double w = 1.0 / std::pow(var_estimate + var_noise, 2);
    num += w * (ebar * ebar - var_estimate - var_noise), den += w;
    b = end;
  }
  return {den > 0 ? num / den : 0.0, den > 0};
}

}  // namespace

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
  std::vector<double> excess;
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
    if (f.valid) excess.push_back(f.value);
  }
  if (excess.size() < 2) return out;
  const double k = static_cast<double>(excess.size());
  double mean = 0.0, sq = 0.0;
  for (const double v : excess) mean += v / k;
  for (const double v : excess) sq += (v - mean) * (v - mean);
  out.mean_excess = mean;
  out.standard_error = std::sqrt(sq / (k - 1) / k);
  out.variance = mean > 2.0 * out.standard_error ? mean : 0.0;
  return out;
}

}  // namespace gyrosid
