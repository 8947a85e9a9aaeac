// A production lot (lot/): the grey-box MAP under a prior against its analytic limits, the population's
// planted modes recovered, the screening null calibrated, planted defects found and named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "core/config.h"
#include "lot/lot_members.h"
#include "lot/lot_model.h"
#include "lot/lot_unit.h"
#include "lot/screen.h"
#include "model/dataset.h"
#include "model/greybox_fit.h"
#include "model/greybox_prior.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;

Dataset noisy_dual_scan(int samples, std::uint64_t seed) {
  TrajectorySpec t = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  t.sampling = Sampling{static_cast<std::size_t>(samples), 0.0};
  const Recording rec = simulate(load_sensor_file("builtin:sensors/open_loop_fog.yaml"), t, seed).recording;
  return make_dataset(rec, greybox_features(GreyboxOptions{}), ModelTarget::error);
}

// The linear-Gaussian identities: a prior equal to the data's own information halves the covariance and
// lands halfway between the least-squares estimate and the prior's mean; a vague prior is the least
// squares; a tight one is its mean.
TEST(GreyboxPrior, TheMapIsThePrecisionWeightedMeanOfDataAndPrior) {
  const Dataset d = noisy_dual_scan(3000, 3);
  const GreyboxOptions o;
  const GreyboxEstimate plain = estimate_greybox(d, o, nullptr);
  const Eigen::MatrixXd c = plain.theta_covariance;
  const Eigen::VectorXd sd = c.diagonal().cwiseSqrt();
  ASSERT_TRUE(sd.allFinite());
  Eigen::VectorXd shift(sd.size());
  RandomStream r(1, "shift");
  for (Eigen::Index j = 0; j < shift.size(); ++j) shift(j) = 3.0 * sd(j) * r.normal();
  const Eigen::VectorXd mu = plain.theta + shift;

  SolveSummary s;
  const GreyboxPrior equal{mu, c, "equal"};
  const GreyboxEstimate half = estimate_greybox(d, o, &equal, &s);
  for (Eigen::Index j = 0; j < sd.size(); ++j) {
    EXPECT_NEAR(half.theta(j), plain.theta(j) + 0.5 * shift(j), 0.02 * sd(j)) << j;
    EXPECT_NEAR(half.theta_covariance(j, j) / c(j, j), 0.5, 0.01) << j;
  }
  EXPECT_NEAR(s.details["data_share"]["surface"].get<double>(), 0.5, 0.01);
  EXPECT_NEAR(s.details["data_share"]["bias"].get<double>(), 0.5, 0.01);

  const GreyboxPrior vague{mu, 1e8 * c, "vague"}, tight{mu, 1e-8 * c, "tight"};
  const GreyboxEstimate v = estimate_greybox(d, o, &vague, &s);
  EXPECT_GT(s.details["data_share"]["surface"].get<double>(), 0.999);
  const GreyboxEstimate t = estimate_greybox(d, o, &tight);
  for (Eigen::Index j = 0; j < sd.size(); ++j) {
    EXPECT_NEAR(v.theta(j), plain.theta(j), 0.01 * sd(j)) << j;
    EXPECT_NEAR(t.theta(j), mu(j), 0.01 * sd(j)) << j;
  }
  const GreyboxPrior wrong_size{mu.head(5), c.topLeftCorner(5, 5), "lot.json"};
  try {
    estimate_greybox(d, o, &wrong_size);
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("lot.json"));
    EXPECT_THAT(e.what(), HasSubstr("5 coordinates where the grey-box structure has 76"));
  }
}

// The conditional score of a one-coordinate term (lot_model.h) against the same Gaussian algebra in information
// form: the recording's own estimate theta^ ~ N(theta, C) (full C) combined with the lot's prior, the term's
// variance freed, P = (C^-1 + Sigma'^-1)^-1, m = P (C^-1 theta^ + Sigma'^-1 mu), z = (m_g - mu_g) / sqrt(P_gg + Sigma_gg).
TEST(LotScreen, TheConditionalScoreIsTheInformationFormsPosterior) {
  GreyboxOptions o;
  o.shupe = true;
  TrajectorySpec t = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  t.sampling = Sampling{3000, 0.0};
  const Recording rec = simulate(load_sensor_file("builtin:sensors/open_loop_fog.yaml"), t, 5).recording;
  const GreyboxEstimate plain = estimate_greybox(make_dataset(rec, greybox_features(o), ModelTarget::error), o, nullptr);
  LotModel lot;
  lot.structure = o;
  lot.coordinates = greybox_coordinates(o);
  ASSERT_EQ(single_coordinate_terms(lot.coordinates), std::vector<std::string>{"shupe"});
  const Eigen::Index p = plain.theta.size(), g = p - 1;
  ASSERT_EQ(lot.coordinates[static_cast<std::size_t>(g)].group, "shupe");
  // A diagonal lot (no modes): each coordinate's sd 3x the recording's own, its mean 2 of them off; Shupe's 4 off.
  const Eigen::VectorXd sd = plain.theta_covariance.diagonal().cwiseSqrt();
  lot.scale = 3.0 * sd, lot.residual_variance = 1.0, lot.modes.resize(p, 0), lot.mode_variance.resize(0);
  lot.mean = plain.theta + 2.0 * sd;
  lot.mean(g) = plain.theta(g) - 4.0 * lot.scale(g);
  const Eigen::VectorXd z = conditional_z(rec, lot);
  ASSERT_EQ(z.size(), 1);

  Eigen::MatrixXd prior_precision = lot.covariance().inverse();
  prior_precision(g, g) = 1.0 / (1e6 * lot.covariance()(g, g));
  const Eigen::MatrixXd data_precision = plain.theta_covariance.inverse();
  const Eigen::MatrixXd post = (data_precision + prior_precision).inverse();
  const Eigen::VectorXd m = post * (data_precision * plain.theta + prior_precision * lot.mean);
  const double expected = (m(g) - lot.mean(g)) / std::sqrt(post(g, g) + lot.covariance()(g, g));
  EXPECT_NEAR(z(0), expected, 1e-3 * std::abs(expected));
  EXPECT_GT(z(0), 3.0);  // 4 lot sd's off, seen through the recording's and the lot's spread
}

// A synthetic lot in the default structure's 76 coordinates: estimation noise sd s (0.05 deg/h on the bias
// values, 5 ppm on the surface), two planted modes of 20 s and 8 s (a surface magnitude, a bias tilt),
// log-normal white noise 10 deg/h x/ exp(0.2).
struct SyntheticLot {
  GreyboxOptions structure = [] { return GreyboxOptions{}; }();
  std::vector<GreyboxCoordinate> coordinates = greybox_coordinates(structure);
  Eigen::Index p = static_cast<Eigen::Index>(coordinates.size());
  Eigen::VectorXd s = Eigen::VectorXd::Constant(p, 5.0), mu = Eigen::VectorXd::Zero(p), a1 = Eigen::VectorXd::Zero(p),
                  a2 = Eigen::VectorXd::Zero(p);
  // With `shupe`, a Shupe coefficient 2 deg/h per (C/min), estimated to 0.05, varying by 0.2 across units.
  explicit SyntheticLot(bool shupe = false) {
    structure.shupe = shupe;
    coordinates = greybox_coordinates(structure);
    p = static_cast<Eigen::Index>(coordinates.size());
    s = Eigen::VectorXd::Constant(p, 5.0), mu = a1 = a2 = Eigen::VectorXd::Zero(p);
    for (Eigen::Index j = 0; j < p; ++j) {
      const auto& c = coordinates[static_cast<std::size_t>(j)];
      if (c.group == "shupe") s(j) = 0.05, mu(j) = 2.0;
      else if (c.group == "bias") s(j) = 0.05, a2(j) = (c.temp_c - 20.0) / 40.0, mu(j) = -15.0 + 0.1 * (c.temp_c - 25.0);
      else a1(j) = -std::pow(c.rate_dps / 100.0, 2) * (1.0 + 0.005 * (c.temp_c - 25.0)), mu(j) = -600.0 * std::pow(c.rate_dps / 100.0, 2);
    }
    a1.normalize(), a2.normalize();
  }
  LotUnit unit(const std::string& name, std::uint64_t seed) const {
    RandomStream r(seed, "unit");
    LotUnit u;
    u.name = name;
    const double z1 = r.normal(), z2 = r.normal();
    u.theta = mu + s.cwiseProduct(20.0 * std::sqrt(static_cast<double>(p)) * z1 * a1 + 8.0 * std::sqrt(static_cast<double>(p)) * z2 * a2);
    for (Eigen::Index j = 0; j < p; ++j) u.theta(j) += s(j) * r.normal();
    if (structure.shupe) u.theta(p - 1) += 0.2 * r.normal();
    u.theta_variance = s.cwiseAbs2();
    u.white_dph_at_1hz = 10.0 * std::exp(0.2 * r.normal());
    return u;
  }
  std::vector<LotUnit> units(int n, std::uint64_t first_seed) const {
    std::vector<LotUnit> out;
    for (int i = 0; i < n; ++i) out.push_back(unit("unit " + std::to_string(i), first_seed + static_cast<std::uint64_t>(i)));
    return out;
  }
};

// cos of the angle between a (standardised by s) and the span of the lot's modes.
double cos_to_modes(const LotModel& lot, const Eigen::VectorXd& a, const Eigen::VectorXd& s) {
  const Eigen::VectorXd z = a.cwiseQuotient(s).cwiseProduct(lot.scale).normalized();
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(lot.modes).householderQ() * Eigen::MatrixXd::Identity(lot.modes.rows(), lot.modes.cols());
  return (q.transpose() * z).norm();
}

TEST(LotModel, RecoversThePlantedModesAndTheNoise) {
  const SyntheticLot g;
  const LotModel lot = learn_lot(g.units(80, 1), {});
  EXPECT_EQ(lot.unit_names.size(), 80u);
  EXPECT_TRUE(lot.left_out.empty());
  ASSERT_EQ(lot.modes.cols(), 2);
  EXPECT_GT(cos_to_modes(lot, g.s.cwiseProduct(g.a1), g.s), 0.99);
  EXPECT_GT(cos_to_modes(lot, g.s.cwiseProduct(g.a2), g.s), 0.99);
  // The scale is the estimation sd; the rest is deconvolved to near zero (floored at a tenth of psi ~ 1).
  EXPECT_NEAR(lot.scale(10), 5.0, 1e-9);
  EXPECT_LT(lot.residual_variance, 0.2);
  // Mean within 4 standard errors per coordinate (the mode's sd 20 s sqrt(p) |a1_j| plus the noise).
  const Eigen::VectorXd sd = lot.covariance().diagonal().cwiseSqrt();
  for (Eigen::Index j = 0; j < g.p; ++j) EXPECT_NEAR(lot.mean(j), g.mu(j), 4.0 * std::max(sd(j), g.s(j)) / std::sqrt(80.0)) << j;
  EXPECT_NEAR(std::exp(lot.log_noise_mean), 10.0, 10.0 * 4.0 * 0.2 / std::sqrt(80.0));
  EXPECT_NEAR(lot.log_noise_sd, 0.2, 0.06);
  // The file's population reads back to the same lot.
  const LotModel back = LotModel::from_json(lot.to_json(), "back");
  EXPECT_EQ(back.covariance(), lot.covariance());
  ASSERT_EQ(back.nulls.size(), lot.nulls.size());
  EXPECT_EQ(back.tests, lot.tests);
  EXPECT_EQ(back.nulls.back().dof, lot.nulls.back().dof);
}

// The population from the units' moments (p x p) against an independent route: the SVD of the N x p matrix of the
// standardised units. The same variances along the same directions, and the same mean.
TEST(LotModel, ItsModesAreTheSvdOfTheStandardisedUnits) {
  const SyntheticLot g;
  const std::vector<LotUnit> units = g.units(80, 1);
  const LotModel lot = learn_lot(units, {});
  ASSERT_TRUE(lot.left_out.empty());
  Eigen::MatrixXd z(80, g.p);
  for (Eigen::Index i = 0; i < 80; ++i) z.row(i) = units[static_cast<std::size_t>(i)].theta.transpose();
  const Eigen::VectorXd mean = z.colwise().mean().transpose();
  for (Eigen::Index j = 0; j < g.p; ++j) EXPECT_NEAR(lot.mean(j), mean(j), 1e-12 * (1.0 + std::abs(mean(j)))) << j;
  z = (z.rowwise() - mean.transpose()) * lot.scale.cwiseInverse().asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(z, Eigen::ComputeThinV);
  const Eigen::Index k = lot.modes.cols();
  ASSERT_EQ(k, 2);
  for (Eigen::Index i = 0; i < k; ++i) {
    const double lambda = svd.singularValues()(i) * svd.singularValues()(i) / 79.0;
    EXPECT_NEAR(lot.mode_variance(i), lambda, 1e-10 * lambda) << i;
    EXPECT_NEAR(std::abs(lot.modes.col(i).normalized().dot(svd.matrixV().col(i))), 1.0, 1e-10) << i;
  }
}

// The leave-one-out lot, downdated from the lot's moments, is the lot learned from the other units afresh.
TEST(LotModel, TheLeaveOneOutDowndateIsTheLotLearnedWithoutTheUnit) {
  const SyntheticLot g;
  std::vector<LotUnit> units = g.units(40, 1);
  LotOptions untrimmed;
  untrimmed.trim_alpha = 0.0;
  const LotModel lot = learn_lot(units, {}, untrimmed);
  const LotModel without = lot_without(lot, LotUnitsInMemory(units), 7, untrimmed);
  units.erase(units.begin() + 7);
  const LotModel afresh = learn_lot(units, {}, untrimmed);
  EXPECT_LT((without.mean - afresh.mean).norm(), 1e-12 * afresh.mean.norm());
  EXPECT_LT((without.covariance() - afresh.covariance()).norm(), 1e-10 * afresh.covariance().norm());
  EXPECT_NE(without.mean, lot.mean);
  try {
    lot_without(lot, LotUnitsInMemory(units), 40);
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("not one the lot was learned from"));
  }
}

// Fresh units of the lot are flagged at about the nominal rate; planted defects are flagged and named.
TEST(LotScreen, TheNullIsCalibratedAndDefectsAreNamed) {
  const SyntheticLot g;
  const LotModel lot = learn_lot(g.units(60, 1), {});
  int alarms = 0;
  const int fresh = 400;
  for (int i = 0; i < fresh; ++i) alarms += screen_unit(lot, g.unit("fresh", 10000 + static_cast<std::uint64_t>(i)), {0.05}).out_of_family;
  EXPECT_GE(alarms, static_cast<int>(0.015 * fresh));
  EXPECT_LE(alarms, static_cast<int>(0.09 * fresh));

  LotUnit ripple = g.unit("ripple", 777);  // +6 sd on the 40 C row's positive rates
  for (Eigen::Index j = 0; j < g.p; ++j) {
    const auto& c = g.coordinates[static_cast<std::size_t>(j)];
    if (c.group == "surface" && c.temp_c == 40.0 && c.rate_dps > 0) ripple.theta(j) += 6.0 * g.s(j);
  }
  const ScreenResult r = screen_unit(lot, ripple);
  EXPECT_TRUE(r.out_of_family);
  EXPECT_LT(r.p_physics, 1e-4);
  ASSERT_FALSE(r.reasons.empty());
  EXPECT_THAT(r.reasons.front(), HasSubstr("surface at 40 C, positive rates"));

  LotUnit noisy = g.unit("noisy", 778);
  noisy.white_dph_at_1hz *= 3.0;
  const ScreenResult n = screen_unit(lot, noisy);
  EXPECT_LT(n.p_noise, 1e-3);
  EXPECT_TRUE(n.out_of_family);
  ASSERT_FALSE(n.reasons.empty());
  EXPECT_THAT(n.reasons.back(), HasSubstr("noise: white"));
}

// A lot that knows its noise from six units (a lot of real replicate units, experiments/production_lot
// real_noise_lot.py): a seventh unit of the same log-normal is flagged for its noise at the nominal rate, because
// its z against the six units' mean and sd is Student's t with 5 dof (the normal's 5 % point, 1.96, is t_5's 10.7 %).
TEST(LotScreen, TheNoiseTestHoldsItsRateOnALotOfSixUnits) {
  const SyntheticLot g;
  LotModel lot = learn_lot(g.units(60, 1), {});
  RandomStream r(5, "six units");
  const int trials = 2000;
  int alarms = 0;
  for (int t = 0; t < trials; ++t) {
    double sum = 0.0, sum2 = 0.0;
    for (int u = 0; u < 6; ++u) {
      const double x = std::log(10.0) + 0.3 * r.normal();
      sum += x, sum2 += x * x;
    }
    lot.noise_units = 6;
    lot.log_noise_mean = sum / 6.0;
    lot.log_noise_sd = std::sqrt((sum2 - sum * sum / 6.0) / 5.0);
    LotUnit unit = g.unit("fresh", 20000 + static_cast<std::uint64_t>(t));
    unit.white_dph_at_1hz = 10.0 * std::exp(0.3 * r.normal());
    alarms += screen_unit(lot, unit).p_noise < 0.05;
  }
  EXPECT_NEAR(static_cast<double>(alarms) / trials, 0.05, 0.015);  // binomial sd 0.005
}

// A Shupe coefficient 4.5 of the lot's sd off (2 -> 2.9 deg/h per C/min) moves one coordinate of 77: the
// omnibus distance hardly notices, the term's own test does, and names it.
// The misfit bins: the default grid's 11 intervals cut in four; a bin's misfit is the mean of its samples' residual
// in standard errors of the residual (its sd over sqrt(count)), and a bin of fewer than 10 samples has none.
TEST(LotMisfit, ABinsMisfitIsItsSamplesMeanResidual) {
  const std::vector<double> edges = misfit_rate_edges_dps(GreyboxOptions{});
  ASSERT_EQ(edges.size(), 45u);
  EXPECT_EQ(edges.front(), -100.0);
  EXPECT_EQ(edges[1], -95.0);
  EXPECT_EQ(edges[21], -5.0);  // [-10, 10] in four
  EXPECT_EQ(edges.back(), 100.0);
  std::vector<double> rates;
  for (int i = 0; i < 400; ++i) {
    const double w = -99.75 + 0.5 * i;
    if (w < -10.0 || w >= -6.5) rates.push_back(w);  // [-10, -5) keeps 4 samples
  }
  const Eigen::VectorXd rate = Eigen::Map<const Eigen::VectorXd>(rates.data(), static_cast<Eigen::Index>(rates.size()));
  const Eigen::VectorXd residual = (3.0 * rate.array() + 1.0).matrix();
  const Eigen::VectorXd m = misfit_by_rate(residual, rate, edges);
  ASSERT_EQ(m.size(), 44);
  const double mean = residual.mean(), sd = std::sqrt((residual.array() - mean).square().sum() / static_cast<double>(residual.size() - 1));
  EXPECT_NEAR(m(0), (3.0 * -97.5 + 1.0) / (sd / std::sqrt(10.0)), 1e-12);  // rates -99.75 .. -95.25: mean -97.5, 10 samples
  EXPECT_NEAR(m(43), (3.0 * 97.5 + 1.0) / (sd / std::sqrt(10.0)), 1e-12);
  EXPECT_NEAR(m(21), (3.0 * -2.5 + 1.0) / (sd / std::sqrt(10.0)), 1e-12);
  EXPECT_TRUE(std::isnan(m(20)));
  EXPECT_NEAR(misfit_by_rate(7.0 * residual, rate, edges)(5), m(5), 1e-12);  // the unit's own noise level divides out
}

// A ripple between the grid's nodes - zero at every node, so the coordinates barely see it - is what the misfit test
// finds and names by its rate; fresh units of the lot pass it at about the nominal rate.
TEST(LotMisfit, ARippleBetweenTheNodesIsFoundAndNamedByItsRate) {
  const SyntheticLot g;
  const auto bins = static_cast<Eigen::Index>(misfit_rate_edges_dps(g.structure).size()) - 1;
  auto with_misfit = [&](LotUnit u, std::uint64_t seed) {
    RandomStream r(seed, "misfit");
    u.misfit.resize(bins);
    for (Eigen::Index b = 0; b < bins; ++b) u.misfit(b) = 0.5 + 2.0 * r.normal();  // a misfit the type shares, and the noise
    return u;
  };
  std::vector<LotUnit> units;
  for (int i = 0; i < 60; ++i) units.push_back(with_misfit(g.unit("unit " + std::to_string(i), 1 + static_cast<std::uint64_t>(i)), 500 + static_cast<std::uint64_t>(i)));
  const LotModel lot = learn_lot(units, {});
  ASSERT_TRUE(lot.misfit.learned());
  EXPECT_NEAR(lot.misfit.null.dof, static_cast<double>(bins), 0.5 * static_cast<double>(bins));  // about chi^2 of the bins
  const LotModel back = LotModel::from_json(lot.to_json(), "back");
  EXPECT_EQ(back.misfit.mean, lot.misfit.mean);
  EXPECT_EQ(back.misfit.null.dof, lot.misfit.null.dof);

  int alarms = 0;
  const int fresh = 400;
  for (int i = 0; i < fresh; ++i) {
    const LotUnit u = with_misfit(g.unit("fresh", 10000 + static_cast<std::uint64_t>(i)), 20000 + static_cast<std::uint64_t>(i));
    alarms += screen_unit(lot, u).tests["misfit"]["p_value"].get<double>() < 0.05;
  }
  EXPECT_GE(alarms, static_cast<int>(0.02 * fresh));
  EXPECT_LE(alarms, static_cast<int>(0.09 * fresh));

  LotUnit ripple = with_misfit(g.unit("ripple", 777), 30000);
  for (Eigen::Index b = 0; b < bins; ++b) {  // 6 dph sin(pi omega / 20 deg/s) at the bin's centre
    const double w = 0.5 * (lot.misfit.rate_edges_dps[static_cast<std::size_t>(b)] + lot.misfit.rate_edges_dps[static_cast<std::size_t>(b) + 1]);
    ripple.misfit(b) += 6.0 * std::sin(M_PI * w / 20.0);
  }
  const ScreenResult r = screen_unit(lot, ripple);
  EXPECT_TRUE(r.out_of_family);
  EXPECT_LT(r.tests["misfit"]["p_value"].get<double>(), 1e-6);
  EXPECT_GT(r.tests["all"]["p_value"].get<double>(), 1e-3);  // its coordinates are the lot's
  ASSERT_FALSE(r.reasons.empty());
  EXPECT_THAT(r.reasons.front(), HasSubstr("misfit at rates"));
}

TEST(LotScreen, ATermsOwnTestFindsWhatTheOmnibusDilutes) {
  const SyntheticLot g(true);
  ASSERT_EQ(g.coordinates.back().group, "shupe");
  LotModel lot = learn_lot(g.units(60, 1), {{"shupe", "true"}});
  ASSERT_EQ(lot.tests.back(), "shupe");
  LotUnit doubled = g.unit("doubled", 900);
  doubled.theta(g.p - 1) += 0.9;
  const ScreenResult r = screen_unit(lot, doubled);
  EXPECT_GT(r.tests["all"]["p_value"].get<double>(), 1e-3);
  EXPECT_LT(r.tests["shupe"]["p_value"].get<double>(), 1e-4);
  EXPECT_TRUE(r.out_of_family);
  ASSERT_FALSE(r.reasons.empty());
  EXPECT_THAT(r.reasons.front(), HasSubstr("shupe: its own test"));
}

TEST(LotModel, AUnitTheOthersDoNotHoldIsLeftOut) {
  const SyntheticLot g;
  std::vector<LotUnit> units = g.units(40, 1);
  units[7].theta(30) += 40.0 * g.s(30);
  const LotModel lot = learn_lot(units, {});
  ASSERT_EQ(lot.left_out.size(), 1u);
  EXPECT_EQ(lot.left_out[0], "unit 7");
  EXPECT_EQ(lot.unit_names.size(), 39u);
  try {
    learn_lot(g.units(4, 1), {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("at least 5"));
  }
}

// In a lot larger than the null's sample (max_loo_units, 200), the units outside the sample are tested too: before,
// only the sampled ones (indices floor(1.5 j) here, so 3k and 3k + 1) could be left out.
TEST(LotModel, AUnitBeyondTheNullsSampleIsLeftOutToo) {
  const SyntheticLot g;
  std::vector<LotUnit> units = g.units(300, 1);
  for (std::size_t i : {2u, 5u, 7u, 101u}) units[i].theta(30) += 40.0 * g.s(30);  // 7 sampled, the others not
  const LotModel lot = learn_lot(units, {});
  EXPECT_EQ(lot.left_out, (std::vector<std::string>{"unit 2", "unit 5", "unit 7", "unit 101"}));
  EXPECT_EQ(lot.unit_names.size(), 296u);
}

// The lot's members (lot_members.h) read back as sensor configs to the coordinates they were written from,
// and their weighted mean and covariance are the population's mean and its covariance within the modes.
TEST(LotMembers, TheUnscentedPointsReadBackToThePopulationsModes) {
  const SyntheticLot g;
  const LotModel lot = learn_lot(g.units(60, 1), {});
  const nlohmann::json members = lot_members(lot);
  const Eigen::Index k = lot.modes.cols();
  ASSERT_EQ(members.size(), static_cast<std::size_t>(2 * k + 1));
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(g.p);
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(g.p, g.p);
  double total = 0.0;
  std::vector<std::pair<double, Eigen::VectorXd>> points;
  for (const auto& m : members) {
    const GyroSensor sensor = load_gyro(ConfigNode::parse(m["sensor"].dump(), "member"));
    points.push_back({m["weight"].get<double>(), greybox_theta(sensor.errors, 0.0, g.structure)});
    total += points.back().first;
    EXPECT_NEAR(units::radps_to_dph(sensor.noise.arw_rad_rt_s), std::exp(lot.log_noise_mean), 1e-9);
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  for (const auto& [w, theta] : points) mean += w * theta;
  for (const auto& [w, theta] : points) cov += w * (theta - mean) * (theta - mean).transpose();
  const Eigen::MatrixXd in_modes = lot.scale.asDiagonal() * lot.modes * lot.modes.transpose() * lot.scale.asDiagonal();
  for (Eigen::Index j = 0; j < g.p; ++j) {
    EXPECT_NEAR(points.front().second(j), lot.mean(j), 1e-6 * (1.0 + std::abs(lot.mean(j)))) << j;  // the mean member is mu
    EXPECT_NEAR(mean(j), lot.mean(j), 1e-6 * (1.0 + std::abs(lot.mean(j)))) << j;
  }
  EXPECT_LT((cov - in_modes).norm(), 1e-6 * in_modes.norm());
}

}  // namespace
}  // namespace gyrosid
