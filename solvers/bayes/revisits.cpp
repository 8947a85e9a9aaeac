#include "solvers/bayes/revisits.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.h"
#include "core/format.h"

namespace gyrosid {

namespace {

constexpr Eigen::Index kQueries = 1000;
constexpr double kNear = 0.1;  // a revisit: within this fraction of a width (Euclidean in width units)

// The residual's own semivariance at a lag of k samples along the record: mean of (r_m - r_{m+k})^2 / 2 over
// every m (pairs at that lag, whatever their inputs).
double semivariance_at(const Eigen::VectorXd& r, Eigen::Index k) {
  const Eigen::Index n = r.size() - k;
  return n > 0 ? 0.5 * (r.tail(n) - r.head(n)).squaredNorm() / static_cast<double>(n) : 0.0;
}

}  // namespace

std::string RevisitCheck::describe() const {
  return str_cat(pairs, " revisits (same inputs within ", kNear, " width, >= ", format_significant(min_lag_s, 3),
                 " s apart) differ by ", format_significant(ratio(), 3), " of what samples as far apart in time differ by");
}

RevisitCheck check_revisits(const Eigen::MatrixXd& x, const Eigen::RowVectorXd& widths, const Eigen::VectorXd& r,
                            const std::vector<double>& t_s, const NoiseModel& model) {
  RevisitCheck out;
  const Eigen::Index n = x.rows();
  if (n < 2 || static_cast<Eigen::Index>(t_s.size()) != n || widths.size() != x.cols()) return out;
  out.min_lag_s = std::max(10.0 * model.dt_s, model.gm_var > 0 ? model.gm_tau_s : 0.0);
  const Eigen::MatrixXd z = x.array().rowwise() / widths.array();
  const Eigen::Index queries = std::min(n, kQueries);
  double observed = 0.0, predicted = 0.0;
  std::map<Eigen::Index, double> along_record;  // semivariance by lag in samples
  for (Eigen::Index q = 0; q < queries; ++q) {
    const Eigen::Index i = q * n / queries;
    const double ti = t_s[static_cast<std::size_t>(i)];
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index nearest = -1;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (std::abs(t_s[static_cast<std::size_t>(j)] - ti) < out.min_lag_s) continue;
      const double d2 = (z.row(j) - z.row(i)).squaredNorm();
      if (d2 < best) best = d2, nearest = j;
    }
    if (nearest < 0 || best > kNear * kNear) continue;
    const double diff = r(i) - r(nearest);
    const Eigen::Index lag = std::abs(nearest - i);
    auto cached = along_record.find(lag);
    if (cached == along_record.end()) cached = along_record.emplace(lag, semivariance_at(r, lag)).first;
    observed += 0.5 * diff * diff;
    predicted += cached->second;
    ++out.pairs;
  }
  if (out.pairs > 0) out.observed = observed / out.pairs, out.predicted = predicted / out.pairs;
  return out;
}

}  // namespace gyrosid
