// The parts of explain that keep it from reporting what the data do not show (issue 12, on recordings of
// an independent generator): held-out samples where the simulation extrapolates (its surface undetermined
// by the training blocks) confirm nothing; the likelihood gate finds a slow Gauss-Markov wander's time
// constant when the Allan fit misplaced it; an effect the held-out blocks cannot test needs strong evidence;
// an effect they do not hold is checked on its own support (issue 34, class 3).
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "explain/heldout_support.h"
#include "explain/judge.h"
#include "explain/noise_likelihood.h"
#include "explain/support_check.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {
namespace {

// A straight line fitted on x in [0, 1]: the leverage of a point x0 is 1/n + (x0 - mean)^2 / Sxx (analytic).
TEST(HeldoutSupport, LeverageOfAStraightLineFlagsOnlyTheExtrapolatedSamples) {
  const int n_train = 1001;
  std::vector<double> xs;
  for (int i = 0; i < n_train; ++i) xs.push_back(i / 1000.0);
  for (double x0 : {0.5, 1.0, 1.3, 2.0, 5.0}) xs.push_back(x0);  // held out
  Eigen::MatrixXd x(static_cast<Eigen::Index>(xs.size()), 2);
  std::vector<char> heldout(xs.size(), 0);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    x.row(static_cast<Eigen::Index>(i)) << 1.0, xs[i];
    heldout[i] = i >= static_cast<std::size_t>(n_train);
  }
  // Mean training leverage p/n = 2/1001; with ratio 10 the threshold is 0.01998. Sxx = n var = 1001 * 0.08350.
  double mean = 0.0, sxx = 0.0;
  for (int i = 0; i < n_train; ++i) mean += xs[static_cast<std::size_t>(i)] / n_train;
  for (int i = 0; i < n_train; ++i) sxx += std::pow(xs[static_cast<std::size_t>(i)] - mean, 2);
  const double threshold = 10.0 * 2.0 / n_train;
  const std::vector<char> out = outside_training_support(x, heldout, 10.0);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double h = 1.0 / n_train + std::pow(xs[i] - mean, 2) / sxx;
    EXPECT_EQ(out[i] != 0, heldout[i] && h > threshold) << xs[i] << " leverage " << h;
  }
  // x0 = 0.5, 1.0 inside (h = 0.001, 0.004); 1.3 (0.0087) inside; 2.0 (0.030) and 5.0 (0.242) outside.
  EXPECT_EQ(out[static_cast<std::size_t>(n_train) + 2], 0);
  EXPECT_EQ(out[static_cast<std::size_t>(n_train) + 3], 1);
  EXPECT_EQ(out[static_cast<std::size_t>(n_train) + 4], 1);
}

// A basis function the training rows never see (a spline knot no training sample is near): any held-out
// sample where it is not zero is outside the support, however small its value.
TEST(HeldoutSupport, AColumnZeroOnTheTrainingRowsMakesItsHeldOutSamplesUnsupported) {
  const int n = 500;
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n + 2, 3);
  std::vector<char> heldout(static_cast<std::size_t>(n + 2), 0);
  RandomStream rng(5, "support");
  for (int i = 0; i < n; ++i) x.row(i) << 1.0, rng.normal(), 0.0;
  x.row(n) << 1.0, 0.1, 0.0;     // inside
  x.row(n + 1) << 1.0, 0.1, 1e-3;  // along the undetermined column
  heldout[static_cast<std::size_t>(n)] = heldout[static_cast<std::size_t>(n + 1)] = 1;
  const std::vector<char> out = outside_training_support(x, heldout, 10.0);
  EXPECT_EQ(out[static_cast<std::size_t>(n)], 0);
  EXPECT_EQ(out[static_cast<std::size_t>(n + 1)], 1);
  for (int i = 0; i < n; ++i) EXPECT_EQ(out[static_cast<std::size_t>(i)], 0);
}

// Signals at 1 Hz with the given probe temperatures (rate zero) and the held-out rows from `first_heldout` on.
ExplainInput temperature_input(const std::vector<double>& temp, std::size_t first_heldout) {
  ExplainInput in;
  const auto n = static_cast<Eigen::Index>(temp.size());
  in.signals.t_s.resize(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) in.signals.t_s[i] = static_cast<double>(i);
  in.signals.rate = Eigen::VectorXd::Zero(n);
  in.signals.temp_c = Eigen::Map<const Eigen::VectorXd>(temp.data(), n);
  in.error = Eigen::VectorXd::Zero(n);
  in.heldout.assign(temp.size(), 0);
  for (std::size_t i = first_heldout; i < temp.size(); ++i) in.heldout[i] = 1;
  return in;
}

// Coverage judged with the judged model's inputs (issue 34). Training: the probe switches between 0 and 40 C
// every 10 s, so a coil lagging it by 600 s stays at 20 C within a ripple of a few tenths; held out: the
// probe held at 0 C, where the lagged coil cools from 20 C towards 0 C. The baseline (bias + a linear
// temperature term at the probe) has seen 0 C on half its training rows and keeps every held-out row; the
// same terms at the lagged temperature are a straight line in T_coil, whose leverage is analytic
// (1/n + (x0 - mean)^2 / Sxx): every held-out row where the coil has left the training ripple is outside.
TEST(HeldoutSupport, ALaggedModelLeavesOutTheHeldOutRowsWhereItsTemperatureLeftTheTrainingRange) {
  const std::size_t n_train = 2000, n_held = 2000;
  std::vector<double> temp{20.0};  // in equilibrium at the mean, so the lagged coil starts inside the ripple
  for (std::size_t i = 1; i < n_train; ++i) temp.push_back((i / 10) % 2 ? 40.0 : 0.0);
  for (std::size_t i = 0; i < n_held; ++i) temp.push_back(0.0);
  const ExplainInput in = temperature_input(temp, n_train);
  const ModelSpec base{{bias_term(), temperature_polynomial({1})}, 0.0};
  const ModelSpec lagged{base.terms, 600.0};
  HeldoutSupport support(in, base, TermScaling::of(in.signals), 10.0);
  for (std::size_t i = 0; i < temp.size(); ++i) ASSERT_EQ(support.baseline()[i], 0) << i;

  const Eigen::VectorXd coil = coil_temperature(in.signals, 600.0).temp_c;
  double mean = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < n_train; ++i) mean += coil(static_cast<Eigen::Index>(i)) / n_train;
  for (std::size_t i = 0; i < n_train; ++i) sxx += std::pow(coil(static_cast<Eigen::Index>(i)) - mean, 2);
  const double threshold = 10.0 * 2.0 / n_train;
  const std::vector<char> out = support.outside({&lagged});
  std::size_t flagged = 0;
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double h = 1.0 / n_train + std::pow(coil(static_cast<Eigen::Index>(i)) - mean, 2) / sxx;
    EXPECT_EQ(out[i] != 0, in.heldout[i] && h > threshold) << i << ": coil " << coil(static_cast<Eigen::Index>(i)) << " C, leverage " << h;
    flagged += out[i];
  }
  // The ripple spans 19.7-20.1 C (Sxx ~ 21 C^2): the coil leaves it within the first few held-out seconds.
  EXPECT_GT(flagged, n_held - 20);
  EXPECT_EQ(out[n_train], 0);  // the first held-out second: the coil is still at 20 C
  EXPECT_EQ(support.outside({&lagged}), out);  // the cached mask
  EXPECT_EQ(support.outside({&base}), support.baseline());
}

// The same for a regressor the baseline does not have: an auxiliary channel v in [0, 1] on the training
// rows and 0.5 or 4 on the held-out rows. With v's column beside the baseline's, exactly the held-out rows
// at v = 4 are outside (leverage ~ 3.5^2 / (n var) = 0.073 against 10 * 3 / n = 0.015); the baseline alone
// keeps them all.
TEST(HeldoutSupport, ARegressorOutsideItsTrainingRangeLeavesOutExactlyThoseHeldOutRows) {
  const std::size_t n_train = 2000;
  std::vector<double> temp, v;
  for (std::size_t i = 0; i < n_train; ++i) temp.push_back((i / 10) % 2 ? 40.0 : 0.0), v.push_back(static_cast<double>(i % 101) / 100.0);
  for (std::size_t i = 0; i < 40; ++i) temp.push_back(i % 2 ? 40.0 : 0.0), v.push_back(i % 4 == 3 ? 4.0 : 0.5);
  ExplainInput in = temperature_input(temp, n_train);
  in.signals.channels["v"] = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  const ModelSpec base{{bias_term(), temperature_polynomial({1})}, 0.0};
  ModelSpec judged = base;
  judged.terms.push_back(channel_term({"v"}));
  HeldoutSupport support(in, base, TermScaling::of(in.signals), 10.0);
  const std::vector<char> out = support.outside({&judged});
  for (std::size_t i = 0; i < temp.size(); ++i) {
    EXPECT_EQ(support.baseline()[i], 0) << i;
    EXPECT_EQ(out[i], i >= n_train && v[i] == 4.0 ? 1 : 0) << i;
  }
}

// White noise (sd 1) plus a Gauss-Markov wander (sd 1, tau 300 s) around a constant: started from a
// time constant five times too short (as an Allan fit under strong white noise may place it), the
// likelihood finds 300 s and the wander's variance; a slow deterministic column shaped like the wander's
// scale (a ramp over a quarter of the record) is not better than the noise re-estimated without it.
TEST(NoiseLikelihood, FindsAMisplacedGaussMarkovTimeConstant) {
  RandomStream rng(21, "gm");
  const Eigen::Index n = 120000;
  const double tau = 300.0, sd = 1.0, phi = std::exp(-1.0 / tau);
  Eigen::VectorXd y(n);
  double gm = sd * rng.normal();
  for (Eigen::Index i = 0; i < n; ++i) {
    gm = phi * gm + sd * std::sqrt(1.0 - phi * phi) * rng.normal();
    y(i) = 3.0 + gm + rng.normal();
  }
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(n));
  std::vector<double> t(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = i, t[static_cast<std::size_t>(i)] = static_cast<double>(i);
  NoiseModel start;
  start.dt_s = 1.0, start.white_var = 1.0, start.gm_var = 0.05, start.gm_tau_s = 60.0;
  const NoiseLikelihood likelihood(rows, t, start);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Ones(n, 1);
  const NoiseLikelihood::Optimum best = likelihood.maximise(x, y);
  EXPECT_NEAR(std::exp(best.log_ratios[2]), tau, 0.3 * tau);  // 400 correlation times: ~7 % sampling error
  EXPECT_NEAR(std::exp(best.log_ratios[1]), sd * sd, 0.3 * sd * sd);
  // A column with nothing of y in it: it cannot raise the maximised likelihood by a BIC penalty's worth.
  Eigen::MatrixXd x2(n, 2);
  x2.col(0).setOnes();
  for (Eigen::Index i = 0; i < n; ++i) x2(i, 1) = i > n / 2 && i < 3 * n / 4 ? static_cast<double>(i - n / 2) / n : 0.0;
  const double l1 = likelihood.maximise(x2, y, best).log_likelihood;
  EXPECT_GE(l1, best.log_likelihood - 1e-6);  // nested: never worse
  EXPECT_LT(2.0 * (l1 - best.log_likelihood) - std::log(static_cast<double>(n)), 0.0);
}

// The acceptance rule: confirmed on held-out blocks (z > 2), or, where they cannot test it, a likelihood-gate
// dBIC of at least the ambiguity level.
TEST(Judge, AnEffectTheHeldOutBlocksCannotTestNeedsStrongEvidenceAgainstTheNoise) {
  Judged j;
  j.stability = 1.0;
  j.heldout_testable = false;
  j.effect.score.ml_delta_bic = 0.11;  // the independent generator's control 9001: a Shupe the wander explains
  EXPECT_FALSE(j.accepted(0.5, 10.0));
  EXPECT_TRUE(j.weak_and_untested(10.0));
  j.effect.score.ml_delta_bic = 231.7;  // a planted Shupe at 0.25 sigma
  EXPECT_TRUE(j.accepted(0.5, 10.0));
  j.heldout_testable = true, j.heldout_z = 1.5, j.effect.score.ml_delta_bic = 0.11;  // testable: held-out z decides
  EXPECT_FALSE(j.accepted(0.5, 10.0));
  j.heldout_z = 2.5;
  EXPECT_TRUE(j.accepted(0.5, 10.0));
  // Held-out blocks that do not hold the effect: their z (side effects of the refit) no longer decides; its
  // own support's does, and the strength gate still applies.
  j.heldout_holds = false, j.heldout_z = 0.2, j.effect.score.ml_delta_bic = 40.4;
  j.support = SupportCheck{700, 0.0, 699.0, true, 6.5};
  EXPECT_TRUE(j.accepted(0.5, 10.0));
  j.support->z = 1.9;
  EXPECT_FALSE(j.accepted(0.5, 10.0));
  j.support->z = 6.5, j.effect.score.ml_delta_bic = 5.0;
  EXPECT_FALSE(j.accepted(0.5, 10.0));
  EXPECT_TRUE(j.weak_and_untested(10.0));
}

// 800 samples at 1 Hz in 8 blocks of 100, blocks 2 and 6 held out (as load_input splits a recording without
// thermal cycles), white noise of unit variance in `error`.
ExplainInput eight_blocks(std::uint64_t seed) {
  ExplainInput in;
  const Eigen::Index n = 800;
  RandomStream rng(seed, "eight blocks");
  in.signals.t_s.resize(n);
  in.error.resize(n);
  in.block.resize(n), in.heldout.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    in.signals.t_s[k] = static_cast<double>(i), in.error(i) = rng.normal();
    in.block[k] = static_cast<int>(i / 100), in.heldout[k] = in.block[k] % 4 == 2;
  }
  in.blocks = 8;
  return in;
}

// The held-out blocks hold an effect when their share of its signal is at least held_share (0.1) of their
// share of the rows (1/4): c = 1 on block 0 and a on block 2 gives a share a^2 / (1 + a^2) against 0.025.
TEST(SupportCheck, TheHeldOutBlocksHoldAnEffectByTheirShareOfItsSignal) {
  const ExplainInput in = eight_blocks(1);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(in.size());
  c.head(100).setOnes();
  EXPECT_FALSE(heldout_blocks_hold(in, {}, c, 0.1));
  c.segment(200, 100).setConstant(0.15);  // share 0.0220
  EXPECT_FALSE(heldout_blocks_hold(in, {}, c, 0.1));
  c.segment(200, 100).setConstant(0.17);  // share 0.0281
  EXPECT_TRUE(heldout_blocks_hold(in, {}, c, 0.1));
  EXPECT_TRUE(heldout_blocks_hold(in, {}, Eigen::VectorXd::Ones(in.size()), 0.1));
  // Rows outside the training support do not count as held: with block 2 outside, the share is 0.
  std::vector<char> outside(static_cast<std::size_t>(in.size()), 0);
  for (std::size_t i = 200; i < 300; ++i) outside[i] = 1;
  EXPECT_FALSE(heldout_blocks_hold(in, outside, c, 0.1));
}

// An onset late in the record, after the last held-out block: a bias step of 1.5 (the noise's sigma) from
// sample 740. Its support is the 60 training samples from there; cross-validated over 4 folds of 15, the
// model with the step predicts each fold from the others (z well over 2). The same columns on the noise
// alone confirm nothing.
TEST(SupportCheck, ALateOnsetIsConfirmedOnItsOwnSupportAndNoiseIsNot) {
  const ExplainInput in = eight_blocks(3);
  Eigen::MatrixXd x_full(in.size(), 2);
  for (Eigen::Index i = 0; i < in.size(); ++i) x_full.row(i) << 1.0, i >= 740 ? 1.0 : 0.0;
  const Eigen::MatrixXd x_minus = x_full.leftCols(1);
  NoiseModel white;  // unit variance
  const Eigen::VectorXd y = in.error + 1.5 * x_full.col(1);
  const Eigen::VectorXd c = 1.5 * x_full.col(1);
  EXPECT_FALSE(heldout_blocks_hold(in, {}, c, 0.1));
  const std::optional<SupportCheck> planted = support_check(in, y, white, x_full, x_minus, c, 1.0, {});
  ASSERT_TRUE(planted.has_value());
  EXPECT_EQ(planted->samples, 60u);
  EXPECT_EQ(planted->t_start_s, 740.0);
  EXPECT_EQ(planted->t_end_s, 799.0);
  EXPECT_TRUE(planted->testable);
  EXPECT_GT(planted->z, 4.0);
  const std::optional<SupportCheck> noise = support_check(in, in.error, white, x_full, x_minus, c, 1.0, {});
  ASSERT_TRUE(noise.has_value());
  EXPECT_LT(noise->z, 2.0);
  // A support too small to fold (fewer than 4 x 10 training samples) is not checked.
  Eigen::VectorXd narrow = Eigen::VectorXd::Zero(in.size());
  narrow.tail(30).setOnes();
  EXPECT_FALSE(support_check(in, y, white, x_full, x_minus, narrow, 1.0, {}).has_value());
}

}  // namespace
}  // namespace gyrosid::explain
