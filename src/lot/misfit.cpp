// The misfit test of lot_model.h MisfitPopulation: the units' mean residual by rate, its population and null.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/checkpoint.h"
#include "core/error.h"
#include "lot/lot_model.h"
#include "nav/statistics.h"

namespace gyrosid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Per bin, Welford's count, mean and sum of squared deviations of the units' misfits that have the bin.
struct BinMoments {
  Eigen::VectorXd count, mean, m2;
  explicit BinMoments(Eigen::Index bins) : count(Eigen::VectorXd::Zero(bins)), mean(Eigen::VectorXd::Zero(bins)), m2(Eigen::VectorXd::Zero(bins)) {}
  void add(const Eigen::VectorXd& x) {
    for (Eigen::Index b = 0; b < x.size(); ++b) {
      if (!std::isfinite(x(b))) continue;
      count(b) += 1.0;
      const double d = x(b) - mean(b);
      mean(b) += d / count(b);
      m2(b) += d * (x(b) - mean(b));
    }
  }
  void remove(const Eigen::VectorXd& x) {  // the exact inverse of add
    for (Eigen::Index b = 0; b < x.size(); ++b) {
      if (!std::isfinite(x(b))) continue;
      const double d = x(b) - mean(b);
      mean(b) = count(b) > 1.0 ? mean(b) - d / (count(b) - 1.0) : 0.0;
      m2(b) = count(b) > 1.0 ? std::max(m2(b) - d * (x(b) - mean(b)), 0.0) : 0.0;
      count(b) -= 1.0;
    }
  }
  // Bins of at least 3 units: their mean and sd (NaN elsewhere).
  void population(MisfitPopulation& out) const {
    out.mean = out.sd = Eigen::VectorXd::Constant(count.size(), kNaN);
    for (Eigen::Index b = 0; b < count.size(); ++b) {
      if (count(b) < 3.0) continue;
      out.mean(b) = mean(b);
      out.sd(b) = std::sqrt(m2(b) / (count(b) - 1.0));
    }
  }
};

}  // namespace

std::vector<double> misfit_rate_edges_dps(const GreyboxOptions& structure) {
  if (structure.scale_factor != ScaleFactorForm::surface) return {};
  const std::vector<double>& grid = structure.surface_rates_dps;
  std::vector<double> edges;
  for (std::size_t i = 0; i + 1 < grid.size(); ++i) {
    for (int q = 0; q < 4; ++q) edges.push_back(grid[i] + 0.25 * q * (grid[i + 1] - grid[i]));
  }
  if (!grid.empty()) edges.push_back(grid.back());
  return edges;
}

Eigen::VectorXd misfit_by_rate(const Eigen::VectorXd& residual_dph, const Eigen::VectorXd& rate_dps, const std::vector<double>& edges_dps) {
  if (edges_dps.size() < 2) return {};
  const auto bins = static_cast<Eigen::Index>(edges_dps.size() - 1);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(bins), count = Eigen::VectorXd::Zero(bins);
  std::vector<Eigen::Index> bin_of(static_cast<std::size_t>(rate_dps.size()), -1);  // -1: outside the bins, or not finite
  for (Eigen::Index i = 0; i < rate_dps.size(); ++i) {
    const double w = rate_dps(i);
    if (!std::isfinite(w) || !std::isfinite(residual_dph(i)) || w < edges_dps.front() || w >= edges_dps.back()) continue;
    const auto b = static_cast<Eigen::Index>(std::upper_bound(edges_dps.begin(), edges_dps.end(), w) - edges_dps.begin()) - 1;
    bin_of[static_cast<std::size_t>(i)] = b;
    sum(b) += residual_dph(i), count(b) += 1.0;
  }
  // In standard errors of the unit's own residual, so a noisier unit is not out of family by its misfit.
  const double used = count.sum();
  double sd = 0.0;
  if (used > 1.0) {
    const double mean = sum.sum() / used;
    for (Eigen::Index i = 0; i < rate_dps.size(); ++i) {
      if (bin_of[static_cast<std::size_t>(i)] >= 0) sd += std::pow(residual_dph(i) - mean, 2);
    }
    sd = std::sqrt(sd / (used - 1.0));
  }
  Eigen::VectorXd misfit(bins);
  for (Eigen::Index b = 0; b < bins; ++b) misfit(b) = count(b) >= 10.0 && sd > 0.0 ? sum(b) / count(b) / (sd / std::sqrt(count(b))) : kNaN;
  return misfit;
}

double MisfitPopulation::distance2(const Eigen::VectorXd& misfit, Eigen::Index* largest) const {
  double d2 = 0.0, top = -1.0;
  if (largest) *largest = -1;
  for (Eigen::Index b = 0; b < std::min(misfit.size(), mean.size()); ++b) {
    if (!std::isfinite(misfit(b)) || !std::isfinite(mean(b)) || !(sd(b) > 0.0)) continue;
    const double z2 = std::pow((misfit(b) - mean(b)) / sd(b), 2);
    d2 += z2;
    if (largest && z2 > top) top = z2, *largest = b;
  }
  return d2;
}

MisfitPopulation learn_misfit(const LotUnits& units, const std::vector<std::size_t>& keep, const std::vector<std::size_t>& loo,
                              std::vector<double> edges_dps) {
  MisfitPopulation out;
  out.rate_edges_dps = std::move(edges_dps);
  const auto bins = static_cast<Eigen::Index>(out.rate_edges_dps.size()) - 1;
  if (bins < 1 || keep.size() < 5) return out;
  BinMoments moments(bins);
  for (std::size_t i : keep) {
    const LotUnit unit = units.at(i);
    if (unit.misfit.size() != bins) return out;  // a unit without (a model file): no test
    moments.add(unit.misfit);
  }
  std::vector<double> distances;  // the null: each unit against the others' bins
  for (std::size_t u : loo) {
    const LotUnit unit = units.at(u);
    BinMoments others = moments;
    others.remove(unit.misfit);
    MisfitPopulation without;
    others.population(without);
    distances.push_back(without.distance2(unit.misfit));
  }
  moments.population(out);
  if (distances.size() < 5 || !(nav::sample_stats(distances).mean > 0.0)) {
    out.mean.resize(0);
    return out;
  }
  out.null = DistanceNull::matched_to(distances);
  return out;
}

nlohmann::json MisfitPopulation::to_json() const {
  auto numbers = [](const Eigen::VectorXd& v) {
    nlohmann::json a = nlohmann::json::array();
    for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(std::isfinite(v(i)) ? nlohmann::json(v(i)) : nlohmann::json());
    return a;
  };
  return {{"rate_edges_dps", rate_edges_dps}, {"mean", numbers(mean)}, {"sd", numbers(sd)},
          {"null", {{"scale", null.scale}, {"dof", null.dof}}}};
}

MisfitPopulation misfit_from_json(const nlohmann::json& j, const std::string& source) {
  MisfitPopulation out;
  out.rate_edges_dps = j.at("rate_edges_dps").get<std::vector<double>>();
  const std::vector<double> mean = saved_numbers(j.at("mean")), sd = saved_numbers(j.at("sd"));
  if (mean.size() != sd.size() || mean.size() + 1 != out.rate_edges_dps.size()) {
    fail(source, ": population.misfit: ", mean.size(), " means and ", sd.size(), " sds for ", out.rate_edges_dps.size(), " rate edges");
  }
  out.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), static_cast<Eigen::Index>(mean.size()));
  out.sd = Eigen::Map<const Eigen::VectorXd>(sd.data(), static_cast<Eigen::Index>(sd.size()));
  out.null = {j.at("null").at("scale").get<double>(), j.at("null").at("dof").get<double>()};
  if (!(out.null.scale > 0.0) || !(out.null.dof > 0.0)) fail(source, ": population.misfit.null: scale and dof must be positive");
  return out;
}

}  // namespace gyrosid
