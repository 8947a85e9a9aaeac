#include "lot/lot_model.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/stats.h"
#include "nav/statistics.h"
#include "sensor/sensor_prior.h"
#include "solvers/calibrate.h"

namespace gyrosid {
namespace {

// The Gaussian of a set of units (rows of theta), before screening.
struct Population {
  Eigen::VectorXd mean, scale, mode_variance;
  Eigen::MatrixXd modes;
  double residual_variance = 0.0;

  Eigen::MatrixXd covariance() const {
    const Eigen::Index p = mean.size();
    const Eigen::MatrixXd z = modes * modes.transpose() + residual_variance * Eigen::MatrixXd::Identity(p, p);
    return scale.asDiagonal() * z * scale.asDiagonal();
  }
};

// The element at index n / 2 of the sorted values (the upper median); x non-empty.
double upper_median(std::vector<double> x) {
  std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
  return x[x.size() / 2];
}

// Per-coordinate scale: the units' sd, floored within its group (a coordinate no unit moves, e.g. a lag all
// units fit as 0, is held by its group's typical spread, or 1 of its unit when the whole group is still).
Eigen::VectorXd coordinate_scale(const Eigen::VectorXd& sd, const std::vector<GreyboxCoordinate>& coordinates) {
  std::map<std::string, std::vector<double>> by_group;
  for (std::size_t i = 0; i < coordinates.size(); ++i) by_group[coordinates[i].group].push_back(sd(static_cast<Eigen::Index>(i)));
  Eigen::VectorXd scale = sd;
  for (std::size_t i = 0; i < coordinates.size(); ++i) {
    const double typical = upper_median(by_group[coordinates[i].group]);
    const auto k = static_cast<Eigen::Index>(i);
    scale(k) = std::max(sd(k), typical > 0.0 ? 1e-3 * typical : 1.0);
  }
  return scale;
}

// Probabilistic PCA of the units from their moments. With the units' estimation sd known, the coordinates are
// scaled by it: the estimation noise is then about white with variance 1, and a mode is kept where its variance
// clears the largest that noise alone shows in a sample of N units, the Marchenko-Pastur edge
// (1 + sqrt(p / (N - 1)))^2. (The rest's own mean is no noise level: a model's misfit and the modes below the
// edge sit in it.) Without it, by the units' sd, the fewest modes holding variance_kept.
// The eigenvalues of the scaled scatter S^-1 C S^-1 / (N - 1), p x p, instead of the SVD of the N x p data: the
// memory is the model's, not the lot's. Forming C squares the data's condition number, which costs the small
// eigenvalues relative accuracy (each is known to about eps lambda_1); none is used alone - a kept mode clears the
// edge (>= 1, the estimation noise) or holds a share of the total, and the rest enter only through their sum,
// the trace, which C holds exactly.
Population fit_population(const UnitMoments& m, const std::vector<GreyboxCoordinate>& coordinates, const LotOptions& o) {
  const auto n = static_cast<Eigen::Index>(m.count), p = m.mean.size();
  Population pop;
  pop.mean = m.mean;
  const Eigen::VectorXd noise_sd = m.estimation_sd();
  pop.scale = coordinate_scale(noise_sd.size() > 0 ? noise_sd : Eigen::VectorXd((m.scatter.diagonal() / (m.count - 1.0)).cwiseSqrt()), coordinates);
  const Eigen::VectorXd inverse = pop.scale.cwiseInverse();
  const Eigen::MatrixXd z_covariance = inverse.asDiagonal() * m.scatter * inverse.asDiagonal() / (m.count - 1.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(z_covariance);
  if (eigen.info() != Eigen::Success) fail("lot: the eigen-decomposition of the units' covariance did not converge");
  const Eigen::VectorXd lambda = eigen.eigenvalues().reverse().cwiseMax(0.0);  // descending
  const Eigen::Index spanned = std::min(n - 1, p), cap = std::min<Eigen::Index>({static_cast<Eigen::Index>(o.max_modes), n - 2, spanned - 1});
  const double total = lambda.sum();
  // psi: the mean variance of the directions the sample spans beyond the k modes.
  auto rest = [&](Eigen::Index k) { return std::max((total - lambda.head(k).sum()) / static_cast<double>(spanned - k), 1e-9 * std::max(total, 1e-300) / static_cast<double>(p)); };
  Eigen::Index k = 0;
  if (noise_sd.size() > 0) {
    const double edge = std::pow(1.0 + std::sqrt(static_cast<double>(p) / static_cast<double>(n - 1)), 2);
    while (k < cap && lambda(k) > edge) ++k;
  } else {
    for (double kept = 0.0; k < cap && kept < o.variance_kept * total; ++k) kept += lambda(k);
  }
  // The modes are lambda - psi over the isotropic rest. With the estimation noise known (variance 1 in these
  // coordinates), the rest is the population's psi - 1 (deconvolved: the units' estimates scatter by their
  // own noise too), floored at a tenth of psi.
  const double psi = rest(k);
  pop.residual_variance = noise_sd.size() > 0 ? std::max(psi - 1.0, 0.1 * psi) : psi;
  pop.mode_variance = lambda.head(k);
  Eigen::MatrixXd directions = eigen.eigenvectors().rightCols(k).rowwise().reverse();
  for (Eigen::Index j = 0; j < k; ++j) {  // each direction's sign: its largest component positive
    Eigen::Index largest = 0;
    directions.col(j).cwiseAbs().maxCoeff(&largest);
    if (directions(largest, j) < 0.0) directions.col(j) *= -1.0;
  }
  pop.modes = directions * (lambda.head(k).array() - psi).cwiseMax(0.0).sqrt().matrix().asDiagonal();
  return pop;
}

}  // namespace

// r' (Sigma + diag(v))^-1 r per test, by Cholesky of the test's block.
std::vector<double> lot_distances(const Eigen::VectorXd& r, const Eigen::MatrixXd& sigma, const Eigen::VectorXd& v,
                                  const std::vector<GreyboxCoordinate>& coordinates, const std::vector<std::string>& tests) {
  Eigen::MatrixXd total = sigma;
  if (v.size() > 0) total.diagonal() += v;
  std::vector<double> out;
  for (const std::string& test : tests) {
    std::vector<Eigen::Index> idx;
    for (std::size_t j = 0; j < coordinates.size(); ++j) {
      if (test == "all" || coordinates[j].group == test) idx.push_back(static_cast<Eigen::Index>(j));
    }
    const Eigen::LLT<Eigen::MatrixXd> llt(total(idx, idx));
    if (llt.info() != Eigen::Success) fail("lot: the covariance of '", test, "' is not positive definite");
    out.push_back(llt.matrixL().solve(Eigen::VectorXd(r(idx))).squaredNorm());
  }
  return out;
}

double DistanceNull::p_value(double d2) const { return 1.0 - stats::chi2_cdf(d2 / scale, dof); }

DistanceNull DistanceNull::matched_to(const std::vector<double>& d2) {
  const nav::SampleStats st = nav::sample_stats(d2);
  const double m = st.mean, v = std::max(st.sigma * st.sigma, 1e-12 * m * m);
  return {v / (2.0 * m), 2.0 * m * m / v};
}

namespace {

// The moments of units[keep], in index order.
UnitMoments moments_of(const LotUnits& units, const std::vector<std::size_t>& keep, Eigen::Index p) {
  UnitMoments m(p);
  for (std::size_t i : keep) m.add(units.at(i));
  return m;
}

// Leave-one-out distances of (at most max_loo_units, evenly spaced) units in `keep`: probes[u] against the
// population of the other units (their moments: those of `keep` less unit u's), index -> d^2 per test.
std::map<std::size_t, std::vector<double>> leave_one_out(const LotUnits& units, const LotUnits& probes, const std::vector<std::size_t>& keep,
                                                         const UnitMoments& moments, const std::vector<GreyboxCoordinate>& coordinates,
                                                         const std::vector<std::string>& tests, const LotOptions& o) {
  std::map<std::size_t, std::vector<double>> d2;
  const std::size_t m = std::min<std::size_t>(keep.size(), static_cast<std::size_t>(o.max_loo_units));
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t u = keep[j * keep.size() / m];
    UnitMoments others = moments;
    others.remove(units.at(u));
    const Population pop = fit_population(others, coordinates, o);
    const LotUnit probe = probes.at(u);
    d2[u] = lot_distances(probe.theta - pop.mean, pop.covariance(), probe.theta_variance, coordinates, tests);
  }
  return d2;
}

// a chi^2_nu with the mean and variance of the distances of test k.
DistanceNull matched_chi2(const std::map<std::size_t, std::vector<double>>& d2, std::size_t k, std::size_t except = SIZE_MAX) {
  std::vector<double> d;
  for (const auto& [u, v] : d2) {
    if (u != except) d.push_back(v[k]);
  }
  return DistanceNull::matched_to(d);
}

// Whether a unit beyond the null's sample (a lot of more than max_loo_units) is out of family, for the trimming:
// first its distance from the population of all the units - holding the unit pulls that population toward it, so
// this distance is about the smaller, and a unit it clears at 1 % (a hundred times trim_alpha's default) stays -
// then, for the few it does not clear, its leave-one-out distance, both against the sample's null.
class TrimScreen {
 public:
  TrimScreen(const UnitMoments& moments, const std::map<std::size_t, std::vector<double>>& d2, const std::vector<GreyboxCoordinate>& coordinates,
             const LotOptions& o)
      : moments_(moments), null_(matched_chi2(d2, 0)), coordinates_(coordinates), o_(o), everyone_(fit_population(moments, coordinates, o)),
        everyone_sigma_(everyone_.covariance()) {}

  bool outside(const LotUnit& unit) const {
    if (p_value(unit, everyone_.mean, everyone_sigma_) >= 0.01) return false;
    UnitMoments others = moments_;
    others.remove(unit);
    const Population pop = fit_population(others, coordinates_, o_);
    return p_value(unit, pop.mean, pop.covariance()) < o_.trim_alpha;
  }

 private:
  double p_value(const LotUnit& unit, const Eigen::VectorXd& mean, const Eigen::MatrixXd& sigma) const {
    return null_.p_value(lot_distances(unit.theta - mean, sigma, unit.theta_variance, coordinates_, {"all"})[0]);
  }
  const UnitMoments& moments_;
  DistanceNull null_;
  const std::vector<GreyboxCoordinate>& coordinates_;
  const LotOptions& o_;
  Population everyone_;
  Eigen::MatrixXd everyone_sigma_;
};

void check_units(const LotUnits& units, Eigen::Index p) {
  if (units.size() < 5) fail("lot: ", units.size(), " units; a lot needs at least 5");
  for (std::size_t i = 0; i < units.size(); ++i) {
    const LotUnit u = units.at(i);
    if (u.theta.size() != p) fail("lot: unit '", u.name, "' has ", u.theta.size(), " coordinates where the structure has ", p);
    if (!u.theta.allFinite()) fail("lot: unit '", u.name, "' has non-finite coordinates");
    if (u.theta_variance.size() != 0 && u.theta_variance.size() != p) {
      fail("lot: unit '", u.name, "' has ", u.theta_variance.size(), " variances where the structure has ", p);
    }
  }
}

}  // namespace

OptionTable LotOptions::table() {
  OptionTable t("lot");
  t.real("variance_kept", &variance_kept, 0.5, 1.0, "share of the units' standardised variance the modes hold")
      .integer("max_modes", &max_modes, 0, 100, "most modes of the population's covariance")
      .real("trim_alpha", &trim_alpha, 0.0, 0.5, "a training unit whose leave-one-out p-value is below this is left out")
      .integer("max_loo_units", &max_loo_units, 5, 100000, "leave-one-out distances of the null from at most this many units");
  return t;
}

std::string LotOptions::validate() const {
  if (!(variance_kept > 0.0 && variance_kept <= 1.0)) return "variance_kept must be in (0, 1]";
  if (max_modes < 0) return "max_modes must be >= 0";
  if (!(trim_alpha >= 0.0 && trim_alpha < 0.5)) return "trim_alpha must be in [0, 0.5)";
  if (max_loo_units < 5) return "max_loo_units must be >= 5";
  return "";
}

Eigen::MatrixXd LotModel::covariance() const {
  return Population{mean, scale, mode_variance, modes, residual_variance}.covariance();
}

GreyboxPrior LotModel::prior() const { return {mean, covariance(), source}; }

UnitMoments::UnitMoments(Eigen::Index p)
    : mean(Eigen::VectorXd::Zero(p)), variance_sum(Eigen::VectorXd::Zero(p)), scatter(Eigen::MatrixXd::Zero(p, p)) {}

void UnitMoments::add(const LotUnit& unit) {
  count += 1.0;
  const Eigen::VectorXd d = unit.theta - mean;
  mean += d / count;
  scatter.noalias() += ((count - 1.0) / count) * d * d.transpose();
  if (unit.theta_variance.size() > 0) variance_sum += unit.theta_variance, variance_count += 1.0;
}

void UnitMoments::remove(const LotUnit& unit) {
  if (count < 2.0) fail("lot: a unit left out of fewer than 2");
  const Eigen::VectorXd d = unit.theta - mean;
  scatter.noalias() -= (count / (count - 1.0)) * d * d.transpose();
  mean -= d / (count - 1.0);
  count -= 1.0;
  if (unit.theta_variance.size() > 0) variance_sum -= unit.theta_variance, variance_count -= 1.0;
}

Eigen::VectorXd UnitMoments::estimation_sd() const {
  if (variance_count != count || count == 0.0) return Eigen::VectorXd();
  return (variance_sum / count).cwiseMax(0.0).cwiseSqrt();
}

LotModel learn_lot(const LotUnits& units, const OptionMap& greybox_options_map, const LotOptions& o, const LotUnits* screen_units) {
  if (auto p = o.validate(); !p.empty()) fail("lot: ", p);
  LotModel lot;
  lot.greybox_options = greybox_options_map;
  lot.structure = gyrosid::greybox_options(greybox_options_map);
  lot.coordinates = greybox_coordinates(lot.structure);
  const auto p = static_cast<Eigen::Index>(lot.coordinates.size());
  check_units(units, p);
  if (screen_units) {
    if (screen_units->size() != units.size()) fail("lot: ", screen_units->size(), " screening recordings for ", units.size(), " units; give one per unit, in the same order");
    check_units(*screen_units, p);
  }

  std::vector<std::size_t> keep(units.size());
  for (std::size_t i = 0; i < units.size(); ++i) keep[i] = i;
  lot.tests = {"all"};
  for (const auto& c : lot.coordinates) {
    if (std::find(lot.tests.begin(), lot.tests.end(), c.group) == lot.tests.end()) lot.tests.push_back(c.group);
  }
  auto moments = std::make_shared<UnitMoments>(moments_of(units, keep, p));
  std::map<std::size_t, std::vector<double>> d2 = leave_one_out(units, units, keep, *moments, lot.coordinates, lot.tests, o);
  if (o.trim_alpha > 0.0) {  // leave out the units the others do not hold (each against the others' null), then learn again
    std::vector<std::size_t> kept;
    std::optional<TrimScreen> rest;  // the units beyond the null's sample
    if (d2.size() < keep.size()) rest.emplace(*moments, d2, lot.coordinates, o);
    for (std::size_t i : keep) {
      const auto it = d2.find(i);
      const bool out = it != d2.end() ? matched_chi2(d2, 0, i).p_value(it->second[0]) < o.trim_alpha : rest->outside(units.at(i));
      if (out) lot.left_out.push_back(units.at(i).name);
      else kept.push_back(i);
    }
    if (kept.size() < 5) fail("lot: only ", kept.size(), " units remain after leaving out those out of family; a lot needs at least 5");
    if (kept.size() != keep.size()) {
      keep = kept;
      moments = std::make_shared<UnitMoments>(moments_of(units, keep, p));
      d2 = leave_one_out(units, units, keep, *moments, lot.coordinates, lot.tests, o);
    }
  }
  const LotUnits& probes = screen_units ? *screen_units : units;  // what the nulls are calibrated on
  if (screen_units) d2 = leave_one_out(units, probes, keep, *moments, lot.coordinates, lot.tests, o);
  const Population pop = fit_population(*moments, lot.coordinates, o);
  lot.mean = pop.mean, lot.scale = pop.scale, lot.modes = pop.modes, lot.mode_variance = pop.mode_variance;
  lot.residual_variance = pop.residual_variance;
  lot.moments = moments;
  lot.kept_units = keep;
  for (const auto& [u, d] : d2) lot.loo_distance.push_back(d[0]), lot.null_units.push_back(u);
  for (std::size_t k = 0; k < lot.tests.size(); ++k) lot.nulls.push_back(matched_chi2(d2, k));
  lot.misfit = learn_misfit(probes, keep, lot.null_units, misfit_rate_edges_dps(lot.structure));

  std::vector<double> log_noise, minutes;
  for (std::size_t i : keep) {
    const LotUnit unit = units.at(i);
    lot.unit_names.push_back(unit.name);
    if (unit.white_dph_at_1hz > 0.0) log_noise.push_back(std::log(unit.white_dph_at_1hz));
    const double probe_min = screen_units ? probes.at(i).recording_min : unit.recording_min;
    if (probe_min > 0.0) minutes.push_back(probe_min);
  }
  lot.noise_units = static_cast<int>(log_noise.size());
  if (!minutes.empty()) lot.recording_min = upper_median(std::move(minutes));
  if (log_noise.size() >= 2) {
    const nav::SampleStats st = nav::sample_stats(log_noise);
    lot.log_noise_mean = st.mean, lot.log_noise_sd = std::max(st.sigma, 0.01);
  }
  return lot;
}

std::vector<std::string> single_coordinate_terms(const std::vector<GreyboxCoordinate>& coordinates) {
  std::map<std::string, int> count;
  for (const auto& c : coordinates) ++count[c.group];
  std::vector<std::string> terms;
  for (const auto& c : coordinates) {
    if (count[c.group] == 1 && c.group != "lag") terms.push_back(c.group);
  }
  return terms;
}

LotModel lot_without(const LotModel& lot, const LotUnits& units, std::size_t u, const LotOptions& o) {
  if (!std::binary_search(lot.kept_units.begin(), lot.kept_units.end(), u) || !lot.moments) fail("lot: unit ", u, " is not one the lot was learned from");
  UnitMoments others = *lot.moments;
  others.remove(units.at(u));
  const Population pop = fit_population(others, lot.coordinates, o);
  LotModel out = lot;
  out.mean = pop.mean, out.scale = pop.scale, out.modes = pop.modes, out.mode_variance = pop.mode_variance;
  out.residual_variance = pop.residual_variance;
  return out;
}

void set_conditional_nulls(LotModel& lot, const std::vector<Eigen::VectorXd>& z) {
  lot.conditional_terms = single_coordinate_terms(lot.coordinates);
  lot.conditional_nulls.clear();
  if (z.size() < 5) fail("lot: ", z.size(), " units' conditional scores; the null needs at least 5");
  std::map<std::size_t, std::vector<double>> z2;
  for (std::size_t u = 0; u < z.size(); ++u) {
    for (Eigen::Index k = 0; k < z[u].size(); ++k) z2[u].push_back(z[u](k) * z[u](k));
  }
  for (std::size_t k = 0; k < lot.conditional_terms.size(); ++k) lot.conditional_nulls.push_back(matched_chi2(z2, k));
}

nlohmann::json LotModel::tests_json() const {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < tests.size(); ++k) out.push_back({{"test", tests[k]}, {"scale", nulls[k].scale}, {"dof", nulls[k].dof}});
  for (std::size_t k = 0; k < conditional_terms.size(); ++k) {
    out.push_back({{"test", conditional_terms[k] + " given the rest"}, {"term", conditional_terms[k]}, {"scale", conditional_nulls[k].scale}, {"dof", conditional_nulls[k].dof}});
  }
  return out;
}

nlohmann::json LotModel::to_json() const {
  nlohmann::json coords = nlohmann::json::array(), mode_rows = nlohmann::json::array();
  for (const auto& c : coordinates) coords.push_back({{"name", c.name}, {"group", c.group}, {"unit", c.unit}});
  for (Eigen::Index k = 0; k < modes.cols(); ++k) mode_rows.push_back(std::vector<double>(modes.col(k).data(), modes.col(k).data() + modes.rows()));
  const Eigen::VectorXd sd = covariance().diagonal().cwiseSqrt();
  auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  nlohmann::json out = {{"model", "greybox"},
           {"greybox_options", greybox_options},
           {"units", unit_names.size()},
           {"recording_min", recording_min},
           {"unit_names", unit_names},
           {"left_out", left_out},
           {"coordinates", coords},
           {"mean", vec(mean)},
           {"sd", vec(sd)},
           {"scale", vec(scale)},
           {"modes", mode_rows},
           {"mode_variance", vec(mode_variance)},
           {"residual_variance", residual_variance},
           {"noise", {{"white_dph_at_1hz", {{"log_mean", log_noise_mean}, {"log_sd", log_noise_sd}, {"units", noise_units}}}}},
           {"screening", {{"null", "scaled chi-square matched to the leave-one-out distances, per test"}, {"tests", tests_json()},
                          {"leave_one_out_d2", loo_distance}}}};
  if (misfit.learned()) out["screening"]["misfit"] = misfit.to_json();
  return out;
}

LotModel LotModel::from_json(const nlohmann::json& j, const std::string& source) {
  LotModel lot;
  lot.source = source;
  try {
    if (j.at("model") != "greybox") fail(source, ": population.model must be greybox");
    lot.greybox_options = j.at("greybox_options").get<OptionMap>();
    lot.structure = gyrosid::greybox_options(lot.greybox_options);
    lot.coordinates = greybox_coordinates(lot.structure);
    const auto p = static_cast<Eigen::Index>(lot.coordinates.size());
    auto vec = [&](const char* key) {
      const auto v = j.at(key).get<std::vector<double>>();
      return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
    };
    lot.mean = vec("mean"), lot.scale = vec("scale"), lot.mode_variance = vec("mode_variance");
    const auto rows = j.at("modes").get<std::vector<std::vector<double>>>();
    lot.modes.resize(p, static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (static_cast<Eigen::Index>(rows[k].size()) != p) fail(source, ": population.modes[", k, "] has ", rows[k].size(), " numbers, expected ", p);
      lot.modes.col(static_cast<Eigen::Index>(k)) = Eigen::Map<const Eigen::VectorXd>(rows[k].data(), p);
    }
    if (lot.mean.size() != p || lot.scale.size() != p) fail(source, ": population.mean and scale need ", p, " numbers (the greybox structure's coordinates)");
    lot.residual_variance = j.at("residual_variance").get<double>();
    lot.unit_names = j.at("unit_names").get<std::vector<std::string>>();
    lot.recording_min = j.value("recording_min", 0.0);
    lot.left_out = j.at("left_out").get<std::vector<std::string>>();
    const auto& noise = j.at("noise").at("white_dph_at_1hz");
    lot.log_noise_mean = noise.at("log_mean"), lot.log_noise_sd = noise.at("log_sd"), lot.noise_units = noise.at("units");
    const auto& s = j.at("screening");
    for (const auto& t : s.at("tests")) {
      const DistanceNull null{t.at("scale").get<double>(), t.at("dof").get<double>()};
      if (!(null.scale > 0.0) || !(null.dof > 0.0)) fail(source, ": population.screening.tests: scale and dof must be positive");
      if (t.contains("term")) {  // a conditional test
        lot.conditional_terms.push_back(t.at("term"));
        lot.conditional_nulls.push_back(null);
      } else {
        lot.tests.push_back(t.at("test"));
        lot.nulls.push_back(null);
      }
    }
    const auto terms = single_coordinate_terms(lot.coordinates);
    if (!lot.conditional_terms.empty() && lot.conditional_terms != terms) {
      fail(source, ": population.screening.tests: the conditional tests must be those of the terms of one coordinate (", join(terms), ")");
    }
    if (lot.tests.empty() || lot.tests.front() != "all") fail(source, ": population.screening.tests must start with 'all'");
    lot.loo_distance = s.at("leave_one_out_d2").get<std::vector<double>>();
    if (s.contains("misfit")) lot.misfit = misfit_from_json(s["misfit"], source);  // lots learned before 2026-11-29 have none
  } catch (const nlohmann::json::exception& e) {
    fail(source, ": population: ", e.what());
  }
  if (!(lot.residual_variance > 0.0)) fail(source, ": population: residual_variance must be positive");
  return lot;
}

std::optional<LotModel> load_lot_if_learned(const std::string& path) {
  nlohmann::json j = nlohmann::json::parse(config_text(path), nullptr, false);
  if (!j.is_object() || !j.contains("population")) return std::nullopt;
  if (j.value("format", "") != kSensorPriorFormat) fail(path, ": format must be '", kSensorPriorFormat, "'");
  return LotModel::from_json(j["population"], path);
}

LotModel load_lot(const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(config_text(path));
  } catch (const nlohmann::json::parse_error& e) {
    fail(path, ": not a JSON lot file (", e.what(), ")");
  }
  if (!j.is_object() || j.value("format", "") != kSensorPriorFormat) fail(path, ": format must be '", kSensorPriorFormat, "'");
  if (!j.contains("population")) fail(path, ": no 'population': a prior over sensors that was not learned from a lot (gyrosid lot learn writes one)");
  return LotModel::from_json(j["population"], path);
}

}  // namespace gyrosid
