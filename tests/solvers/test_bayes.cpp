// The evidence-maximising RBF (solvers/bayes) against independent computations: the log marginal likelihood
// against the brute-force N x N Gaussian-process formula (white and coloured noise), its width gradient
// against finite differences, the Kalman whitener against the explicit noise covariance, the known-noise
// posterior against the Cramer-Rao bound (F' Sigma^-1 F)^-1, planted widths and noise recovered, the 95 %
// predictive band's coverage on data drawn from the prior, and coloured noise kept out of the surface.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <cstdio>
#include <optional>

#include "core/random.h"
#include "core/units.h"
#include "model/gaussian_node.h"
#include "noise/state_space.h"
#include "sim/simulate.h"
#include "solvers/bayes/bayes_fit.h"
#include "solvers/bayes/evidence.h"
#include "solvers/bayes/hybrid_fit.h"
#include "solvers/bayes/model_error.h"
#include "solvers/common/candidates.h"

namespace gyrosid {
namespace {

constexpr double kLog2Pi = 1.8378770664093454836;

Eigen::MatrixXd uniform_inputs(Eigen::Index n, std::uint64_t seed) {
  RandomStream r(seed, "bayes-test/x");
  Eigen::MatrixXd x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) x(i, 0) = -1 + 2 * r.uniform(), x(i, 1) = -1 + 2 * r.uniform();
  return x;
}

std::vector<double> unit_times(Eigen::Index n) {
  std::vector<double> t(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = static_cast<double>(i);
  return t;
}

// A rate cycle and a temperature scan: input 0 = sin(2 pi i / period + phase), input 1 a ramp -1..1 over the n
// samples.
Eigen::MatrixXd sine_and_ramp(Eigen::Index n, double period, double phase = 0.0) {
  Eigen::MatrixXd x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    x(i, 0) = std::sin(2 * M_PI * t / period + phase), x(i, 1) = -1 + 2 * t / static_cast<double>(n - 1);
  }
  return x;
}

// The covariance the whitener stands for, written out: white v I + Gauss-Markov s^2 exp(-|t_i - t_j|/tau)
// + a random walk started at zero at the first sample, q min(k_i, k_j) (k in sample intervals).
Eigen::MatrixXd noise_covariance(const NoiseModel& m, const std::vector<double>& t) {
  const auto n = static_cast<Eigen::Index>(t.size());
  Eigen::MatrixXd c(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      const double ti = t[static_cast<std::size_t>(i)] - t[0], tj = t[static_cast<std::size_t>(j)] - t[0];
      c(i, j) = (i == j ? m.white_var : 0.0) + m.rw_q * std::min(ti, tj) / m.dt_s +
                (m.gm_var > 0 ? m.gm_var * std::exp(-std::abs(ti - tj) / m.gm_tau_s) : 0.0);
    }
  return c;
}

NoiseModel coloured_model() {
  NoiseModel m;
  m.dt_s = 1.0, m.white_var = 0.04, m.rw_q = 1e-4, m.gm_var = 0.09, m.gm_tau_s = 7.0;
  return m;
}

std::vector<Eigen::Index> all_rows(Eigen::Index n) {
  std::vector<Eigen::Index> rows(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = i;
  return rows;
}

TEST(Whitener, IsTheInverseSquareRootOfTheNoiseCovarianceAndItsAdjointItsTranspose) {
  const Eigen::Index n = 40;
  std::vector<double> t = unit_times(n);
  t[20] += 3.0;  // a gap: the states propagate over it
  for (std::size_t i = 21; i < t.size(); ++i) t[i] += 3.0;
  const NoiseModel m = coloured_model();
  const Whitener w(m, all_rows(n), t, RandomWalkStart::zero);
  const Eigen::MatrixXd wm = w.apply(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd c = noise_covariance(m, t);
  EXPECT_LT((wm * c * wm.transpose() - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_NEAR(w.log_determinant(), std::log(c.determinant()), 1e-9);
  RandomStream r(3, "adjoint");
  Eigen::MatrixXd z(n, 3);
  for (Eigen::Index i = 0; i < z.size(); ++i) z(i) = r.normal();
  EXPECT_LT((w.apply_transpose(z, n) - wm.transpose() * z).cwiseAbs().maxCoeff(), 1e-12);
}

// A small problem: y = 0.4 + 0.3 x0 + sum_j w_j phi_j + noise, M = 12 nodes at a farthest-point subset.
struct Small {
  Eigen::MatrixXd x = uniform_inputs(80, 5);
  Eigen::MatrixXd centres = rows_of(x, select_candidates(x, 12));
  Eigen::RowVectorXd widths = Eigen::RowVector2d(0.35, 0.6);
  Eigen::MatrixXd f;
  Eigen::VectorXd y;
  Small() {
    f.resize(x.rows(), 2);
    f.col(0).setOnes(), f.col(1) = x.col(0);
    RandomStream r(7, "small");
    Eigen::VectorXd w(centres.rows());
    for (Eigen::Index j = 0; j < w.size(); ++j) w(j) = r.normal();
    y = gaussian_columns(x, centres, widths) * w + 0.4 * f.col(0) + 0.3 * f.col(1);
    for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += 0.2 * r.normal();
  }
  BayesProblem problem() const {
    BayesProblem p;
    p.x = x, p.y = y, p.fixed = f, p.t_s = unit_times(x.rows());
    return p;
  }
};

// log p(y) = -1/2 [(N - P) log 2 pi + log|K| + log|F'K^-1 F| + y' Pi y],  K = Phi Phi'/alpha + Sigma_0/beta,
// Pi = K^-1 - K^-1 F (F'K^-1 F)^-1 F'K^-1: y = F v + Phi w + e with v flat, w ~ N(0, I/alpha).
double brute_force_log_evidence(const Small& s, const Eigen::MatrixXd& sigma0, double alpha, double beta) {
  const Eigen::MatrixXd phi = gaussian_columns(s.x, s.centres, s.widths);
  const Eigen::MatrixXd k = phi * phi.transpose() / alpha + sigma0 / beta;
  const Eigen::LLT<Eigen::MatrixXd> kl(k);
  const Eigen::MatrixXd kf = kl.solve(s.f);
  const Eigen::MatrixXd fkf = s.f.transpose() * kf;
  const Eigen::VectorXd ky = kl.solve(s.y);
  const Eigen::VectorXd fky = s.f.transpose() * ky;
  const double quad = s.y.dot(ky) - fky.dot(fkf.ldlt().solve(fky));
  const double n = static_cast<double>(s.y.size()), p = static_cast<double>(s.f.cols());
  const double log_det_k = 2.0 * Eigen::MatrixXd(kl.matrixL()).diagonal().array().log().sum();
  return -0.5 * ((n - p) * kLog2Pi + log_det_k + std::log(fkf.determinant()) + quad);
}

TEST(BayesEvidence, EqualsTheBruteForceGaussianProcessMarginalLikelihood) {
  const Small s;
  const NoiseModel m = coloured_model();
  const Whitener w(m, all_rows(s.x.rows()), unit_times(s.x.rows()), RandomWalkStart::zero);
  for (const Whitener* whitener : {static_cast<const Whitener*>(nullptr), &w}) {
    const FixedPart fixed(s.f, s.y, whitener);
    Eigen::MatrixXd phi_p = gaussian_columns(s.x, s.centres, s.widths);
    fixed.project(phi_p);
    const RbfEvidence ev(phi_p, fixed);
    const Eigen::MatrixXd sigma0 = whitener ? noise_covariance(m, unit_times(s.x.rows())) : Eigen::MatrixXd::Identity(80, 80);
    for (const auto& [alpha, beta] : {std::pair{0.5, 20.0}, {3.0, 1.0}, {0.05, 300.0}}) {
      const double ours = ev.log_evidence({std::log(alpha), std::log(beta)});
      EXPECT_NEAR(ours, brute_force_log_evidence(s, sigma0, alpha, beta), 1e-8 * std::abs(ours))
          << (whitener ? "coloured" : "white") << " alpha " << alpha << " beta " << beta;
    }
  }
}

TEST(BayesEvidence, FixedPointIsTheMaximumOverPriorAndNoisePrecision) {
  const Small s;
  const FixedPart fixed(s.f, s.y, nullptr);
  Eigen::MatrixXd phi_p = gaussian_columns(s.x, s.centres, s.widths);
  fixed.project(phi_p);
  RbfEvidence ev(phi_p, fixed);
  const double best = ev.optimise({0.0, 0.0});
  const Precisions at = ev.precisions();
  for (double da : {-0.05, 0.05})
    for (double db : {-0.05, 0.05}) EXPECT_LT(ev.log_evidence({at.log_alpha + da, at.log_beta + db}), best);
  // The noise precision found is near the planted 1 / 0.2^2 = 25.
  EXPECT_NEAR(std::exp(-0.5 * at.log_beta), 0.2, 0.05);
}

TEST(BayesEvidence, WidthGradientMatchesFiniteDifferences) {
  const Small s;
  const BayesProblem p = s.problem();
  const NoiseModel m = coloured_model();
  const Whitener w(m, all_rows(s.x.rows()), p.t_s, RandomWalkStart::zero);
  for (const Whitener* whitener : {static_cast<const Whitener*>(nullptr), &w}) {
    const FixedPart fixed(p.fixed, p.y, whitener);
    const Eigen::RowVectorXd widths(Eigen::RowVector2d(0.3, 0.8));
    Eigen::VectorXd g;
    const EvidenceAt at = evidence_at(p, s.centres, widths, fixed, false, {0.0, 0.0}, &g);
    for (Eigen::Index k = 0; k < 2; ++k) {
      const double h = 1e-5;
      Eigen::RowVectorXd up = widths, down = widths;
      up(k) *= std::exp(h), down(k) *= std::exp(-h);
      const double fd = (evidence_at(p, s.centres, up, fixed, false, at.precisions, nullptr).value -
                         evidence_at(p, s.centres, down, fixed, false, at.precisions, nullptr).value) / (2 * h);
      EXPECT_NEAR(g(k), fd, 1e-5 * (1 + std::abs(fd))) << (whitener ? "coloured" : "white") << ", input " << k;
    }
  }
}

TEST(BayesFit, KnownNoiseWithoutNodesGivesTheCramerRaoBound) {
  const Small s;
  BayesProblem p = s.problem();
  const NoiseModel m = coloured_model();
  p.given_noise = m;
  BayesFitOptions o;
  o.nodes = 0;
  SolveMonitor monitor;
  const BayesFit fit = fit_bayes(p, o, monitor);
  const Eigen::MatrixXd sigma = noise_covariance(m, p.t_s);
  const Eigen::MatrixXd fisher = s.f.transpose() * sigma.llt().solve(s.f);
  const Eigen::MatrixXd crb = fisher.inverse();
  EXPECT_LT((fit.covariance - crb).cwiseAbs().maxCoeff(), 1e-9 * crb.cwiseAbs().maxCoeff());
  // The estimate is the generalised least-squares one.
  const Eigen::VectorXd gls = crb * (s.f.transpose() * sigma.llt().solve(s.y));
  EXPECT_LT((fit.fixed_weights - gls).cwiseAbs().maxCoeff(), 1e-9);
}

// A function drawn from the model's own prior: M nodes (farthest-point centres) with widths r, weights N(0, 1).
struct Drawn {
  Eigen::MatrixXd x, centres;
  Eigen::VectorXd truth, y;
};

Drawn draw(Eigen::Index n, int m, const Eigen::RowVectorXd& widths, double noise, std::uint64_t seed) {
  Drawn d;
  d.x = uniform_inputs(n, seed);
  d.centres = rows_of(d.x, select_candidates(d.x, m));
  RandomStream r(seed, "bayes-test/draw");
  Eigen::VectorXd w(m);
  for (Eigen::Index j = 0; j < m; ++j) w(j) = r.normal();
  d.truth = gaussian_columns(d.x, d.centres, widths) * w;
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) d.y(i) += noise * r.normal();
  return d;
}

BayesProblem problem_of(const Drawn& d) {
  BayesProblem p;
  p.x = d.x, p.y = d.y, p.fixed = Eigen::MatrixXd::Ones(d.y.size(), 1), p.t_s = unit_times(d.y.size());
  return p;
}

TEST(BayesFit, RecoversPlantedWidthsPriorAndNoise) {
  const Drawn d = draw(3000, 60, Eigen::RowVector2d(0.25, 0.6), 0.05, 21);
  BayesFitOptions o;
  o.nodes = 60, o.noise = "white";
  SolveMonitor monitor;
  const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
  EXPECT_NEAR(fit.widths(0), 0.25, 0.025);
  EXPECT_NEAR(fit.widths(1), 0.6, 0.06);
  EXPECT_NEAR(fit.noise_sigma, 0.05, 0.0025);
  EXPECT_GT(std::exp(fit.log_alpha), 0.4);  // planted weights have unit variance: alpha = 1
  EXPECT_LT(std::exp(fit.log_alpha), 2.5);
  EXPECT_EQ(fit.termination, Termination::converged) << fit.message;
}

TEST(BayesFit, NinetyFivePercentBandCoversDataDrawnFromThePrior) {
  int inside = 0, total = 0;
  for (int rep = 0; rep < 12; ++rep) {
    const Drawn d = draw(600, 30, Eigen::RowVector2d(0.3, 0.5), 0.1, 100 + static_cast<std::uint64_t>(rep));
    BayesFitOptions o;
    o.nodes = 30, o.noise = "white", o.scan = 4;
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
    const Eigen::MatrixXd test = uniform_inputs(200, 900 + static_cast<std::uint64_t>(rep));
    Eigen::MatrixXd h(test.rows(), fit.centres.rows() + 1);
    h.leftCols(fit.centres.rows()) = gaussian_columns(test, fit.centres, fit.widths);
    h.col(fit.centres.rows()).setOnes();
    Eigen::VectorXd weights(fit.centres.rows() + 1);
    weights << fit.rbf_weights, fit.fixed_weights;
    // The truth at the test points (same drawn weights: regenerate them).
    RandomStream r(100 + static_cast<std::uint64_t>(rep), "bayes-test/draw");
    Eigen::VectorXd w(30);
    for (Eigen::Index j = 0; j < 30; ++j) w(j) = r.normal();
    const Eigen::VectorXd truth = gaussian_columns(test, d.centres, Eigen::RowVectorXd(Eigen::RowVector2d(0.3, 0.5))) * w;
    const Eigen::VectorXd estimate = h * weights;
    const Eigen::VectorXd sigma = (h * fit.covariance * h.transpose()).diagonal().cwiseSqrt();
    for (Eigen::Index i = 0; i < test.rows(); ++i, ++total) inside += std::abs(estimate(i) - truth(i)) <= 1.96 * sigma(i);
  }
  const double coverage = static_cast<double>(inside) / total;
  EXPECT_GT(coverage, 0.90);
  EXPECT_LT(coverage, 0.99);
}

TEST(BayesFit, LevelledInputsBoundTheirWidthsBelowByTheLevelSpacing) {
  // Input 0 on 9 levels 0.25 apart (with jitter below the level gap), input 1 a continuous ramp.
  const Eigen::Index n = 3600;
  Drawn d;
  d.x.resize(n, 2);
  RandomStream r(7, "levels");
  for (Eigen::Index i = 0; i < n; ++i) {
    d.x(i, 0) = -1 + 0.25 * static_cast<double>((i * 5) % 9) + 1e-4 * r.normal();
    d.x(i, 1) = -1 + 2 * static_cast<double>(i) / static_cast<double>(n - 1);
  }
  const std::vector<double> bounds = identifiable_min_widths(d.x, 0.02);
  EXPECT_NEAR(bounds[0], 0.25, 1e-3);
  EXPECT_DOUBLE_EQ(bounds[1], 0.02);
  EXPECT_DOUBLE_EQ(identifiable_min_widths(uniform_inputs(500, 3), 0.02)[0], 0.02);

  // A surface with structure near the level spacing, learnt on the levels, is still predicted halfway between them.
  auto truth = [](const Eigen::MatrixXd& x) { return ((8.0 * x.col(0).array()).sin() * (1 + 0.5 * x.col(1).array())).matrix().eval(); };
  d.truth = truth(d.x);
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) d.y(i) += 0.05 * r.normal();
  BayesFitOptions o;
  o.nodes = 80, o.noise = "white";
  SolveMonitor monitor;
  const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
  EXPECT_GE(fit.widths(0), bounds[0] - 1e-12);
  Eigen::MatrixXd mid(8 * 21, 2);
  for (Eigen::Index i = 0; i < 8; ++i) {
    for (Eigen::Index j = 0; j < 21; ++j) mid(i * 21 + j, 0) = -0.875 + 0.25 * static_cast<double>(i), mid(i * 21 + j, 1) = -1 + 0.1 * static_cast<double>(j);
  }
  Eigen::MatrixXd h(mid.rows(), fit.centres.rows() + 1);
  h.leftCols(fit.centres.rows()) = gaussian_columns(mid, fit.centres, fit.widths);
  h.col(fit.centres.rows()).setOnes();
  Eigen::VectorXd weights(fit.centres.rows() + 1);
  weights << fit.rbf_weights, fit.fixed_weights;
  const Eigen::VectorXd error = h * weights - truth(mid);
  const double rms = std::sqrt(error.squaredNorm() / static_cast<double>(error.size()));
  // Unbounded, the evidence picks a width of 0.077 and leaves 0.70 rms halfway (0.084 bounded).
  EXPECT_LT(rms, 0.2) << "widths " << fit.widths;
}

TEST(BayesFit, GaussMarkovDriftIsNoiseNotSurface) {
  // A smooth function of two inputs cycling in time, plus Gauss-Markov drift (tau 150 samples) and white noise.
  const Eigen::Index n = 4000;
  Drawn d;
  d.x = sine_and_ramp(n, 97.0);
  d.truth = (1.5 * d.x.col(0).array() * d.x.col(1).array() + 0.5 * (3 * d.x.col(0).array()).sin()).matrix();
  RandomStream r(31, "gm");
  const double phi = std::exp(-1.0 / 150.0);
  double g = 0.3 * r.normal();
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) {
    g = phi * g + 0.3 * std::sqrt(1 - phi * phi) * r.normal();
    d.y(i) += g + 0.1 * r.normal();
  }
  auto fit_with = [&](const std::string& noise) {
    BayesFitOptions o;
    o.nodes = 60, o.noise = noise;
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
    const Eigen::VectorXd f = gaussian_columns(d.x, fit.centres, fit.widths) * fit.rbf_weights +
                              Eigen::VectorXd::Constant(n, fit.fixed_weights(0));
    return std::pair{fit, std::sqrt((f - d.truth).array().square().mean())};
  };
  const auto [white, white_rms] = fit_with("white");
  const auto [coloured, coloured_rms] = fit_with("auto");
  ASSERT_TRUE(coloured.noise.has_value()) << coloured.noise_choice;
  EXPECT_LT(coloured_rms, 0.7 * white_rms) << "white " << white_rms << ", coloured " << coloured_rms << ": " << coloured.noise_choice;
  EXPECT_GT(coloured.noise->gm_tau_s, 50.0);
  EXPECT_LT(coloured.noise->gm_tau_s, 450.0);
}


// 3 h at 1 Hz (n samples) of a fast input cycling (a rate, period 97 s) and a slow triangle (a temperature
// scanned up and down twice), with a smooth truth on them; y is left to the test.
Drawn three_hour_scan(Eigen::Index n) {
  Drawn d;
  d.x.resize(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i), phase = std::fmod(4.0 * t / static_cast<double>(n), 2.0);
    d.x(i, 0) = std::sin(2 * M_PI * t / 97.0), d.x(i, 1) = -1 + 2 * (phase < 1 ? phase : 2 - phase);
  }
  d.truth = (1.5 * d.x.col(0).array() * (1 + 0.3 * d.x.col(1).array()) + 0.5 * d.x.col(1).array().square()).matrix();
  return d;
}

TEST(BayesFit, SlowGaussMarkovWanderIsNotTakenForARandomWalk) {
  // White noise 0.1, Gauss-Markov 0.3 at tau 600 samples and a small random walk (increment variance 7e-7
  // per sample: 1/430 of the q = 2 sigma^2 / tau that the wander looks like above 1/(2 pi tau), as
  // other_fog.yaml's 0.5 deg/h/rt(h) against its GM 3 deg/h at 600 s), on 3 h at 1 Hz of a fast input
  // cycling (a rate) and a slow triangle (a temperature scanned up and down twice). Above 1/(2 pi tau) the
  // wander is a random walk of q = 3e-4, so a search may take it for one; the walk has no level, and the
  // fit would then waste the slow information on the constant. noise=auto must find the wander: tau within
  // a factor 2 of 600, the walk not ten times its planted size, and the surface about as good as with the
  // noise model given.
  const Eigen::Index n = 10800;
  Drawn d = three_hour_scan(n);
  NoiseModel planted;
  planted.dt_s = 1.0, planted.white_var = 0.01, planted.rw_q = 7e-7, planted.gm_var = 0.09, planted.gm_tau_s = 600.0;
  RandomStream r(17, "slow-wander");
  const double phi = std::exp(-1.0 / planted.gm_tau_s);
  double g = 0.3 * r.normal(), w = 0.0;
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) {
    g = phi * g + 0.3 * std::sqrt(1 - phi * phi) * r.normal();
    w += std::sqrt(planted.rw_q) * r.normal();
    d.y(i) += g + w + 0.1 * r.normal();
  }
  auto fit_with = [&](const std::optional<NoiseModel>& given) {
    BayesFitOptions o;
    o.nodes = 30, o.model_error = "none", o.noise = given ? "given" : "auto";
    BayesProblem p = problem_of(d);
    p.given_noise = given;
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(p, o, monitor);
    const Eigen::VectorXd f = gaussian_columns(d.x, fit.centres, fit.widths) * fit.rbf_weights +
                              Eigen::VectorXd::Constant(n, fit.fixed_weights(0));
    return std::pair{fit, std::sqrt((f - d.truth).array().square().mean())};
  };
  const auto [fit, rms] = fit_with(std::nullopt);
  ASSERT_TRUE(fit.noise.has_value()) << fit.noise_choice;
  EXPECT_GT(fit.noise->gm_tau_s, 300.0) << fit.noise_choice;
  EXPECT_LT(fit.noise->gm_tau_s, 1200.0) << fit.noise_choice;
  EXPECT_LT(fit.noise->rw_q, 10 * planted.rw_q) << fit.noise_choice;
  const double given_rms = fit_with(planted).second;
  EXPECT_LT(rms, 1.5 * given_rms) << "auto " << rms << " (" << fit.noise_choice << "), given " << given_rms;
}

TEST(BayesFit, ARandomWalkKeepsItsIntensity) {
  // The other side of SlowGaussMarkovWanderIsNotTakenForARandomWalk: on the same trajectory, white noise 0.1
  // and a random walk alone (increment variance q = 3e-5 per sample: 0.57 after the 3 h). On the record a
  // walk and a Gauss-Markov wander with tau near the span are the same process (the evidence ties them), and
  // noise=auto then keeps the wander (bayes_fit.cpp, nested_noise_by_evidence). What the record does tell
  // must be right: the intensity q + 2 sigma^2 dt / tau within 2x of the planted q, and a wander, if chosen,
  // slower than half the span (no shorter time constant the record would show).
  const Eigen::Index n = 10800;
  Drawn d = three_hour_scan(n);
  const double q = 3e-5;
  RandomStream r(19, "walk");
  double w = 0.0;
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) {
    w += std::sqrt(q) * r.normal();
    d.y(i) += w + 0.1 * r.normal();
  }
  BayesFitOptions o;
  o.nodes = 30, o.model_error = "none";
  SolveMonitor monitor;
  const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
  ASSERT_TRUE(fit.noise.has_value()) << fit.noise_choice;
  const NoiseModel& m = *fit.noise;
  const double intensity = m.rw_q + (m.gm_var > 0 ? 2 * m.gm_var * m.dt_s / m.gm_tau_s : 0.0);
  EXPECT_GT(intensity, 0.5 * q) << fit.noise_choice;
  EXPECT_LT(intensity, 2.0 * q) << fit.noise_choice;
  if (m.gm_var > m.white_var) {
    EXPECT_GT(m.gm_tau_s, 0.5 * static_cast<double>(n)) << fit.noise_choice;
  }
}

TEST(BayesFit, MisfitCorrelatedInTimeIsNotTakenForDriftWhereTheInputsRevisit) {
  // A trajectory that revisits its inputs (input 1 a triangle wave: up, down, up) and a truth with a kink
  // the Gaussian nodes cannot follow, noise-free but for a 1e-4 white floor: the white fit's misfit is
  // smooth in time, so a coloured noise model raises its likelihood, but it repeats at the revisits and is
  // no drift. noise=auto must keep white noise - the same fit as noise=white. With Gauss-Markov drift added
  // (tau 150 samples) on the same trajectory, the revisits differ by the drift and auto must go coloured.
  const Eigen::Index n = 3000;
  Drawn d;
  d.x.resize(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i), phase = std::fmod(3.0 * t / static_cast<double>(n), 2.0);
    d.x(i, 0) = std::sin(2 * M_PI * t / 53.0), d.x(i, 1) = -1 + 2 * (phase < 1 ? phase : 2 - phase);
  }
  d.truth = (d.x.col(0).array() * (1 + 0.3 * d.x.col(1).array()) + 0.4 * (d.x.col(1).array() - 0.2).abs()).matrix();
  RandomStream r(41, "revisits");
  d.y = d.truth;
  for (Eigen::Index i = 0; i < n; ++i) d.y(i) += 1e-4 * r.normal();
  auto fit_with = [&](const std::string& noise, const std::string& averaging = "mixture") {
    BayesFitOptions o;
    o.nodes = 40, o.noise = noise, o.model_error = "none", o.drift_averaging = averaging;
    SolveMonitor monitor;
    return fit_bayes(problem_of(d), o, monitor);
  };
  const BayesFit misfit = fit_with("auto");
  EXPECT_FALSE(misfit.noise.has_value()) << misfit.noise_choice;
  EXPECT_NE(misfit.noise_choice.find("misfit"), std::string::npos) << misfit.noise_choice;  // the screen saw correlation
  EXPECT_EQ(misfit.rbf_weights, fit_with("white").rbf_weights);

  const double phi = std::exp(-1.0 / 150.0);
  double g = 0.3 * r.normal();
  for (Eigen::Index i = 0; i < n; ++i) {
    g = phi * g + 0.3 * std::sqrt(1 - phi * phi) * r.normal();
    d.y(i) += g + 0.05 * r.normal();
  }
  const BayesFit drift = fit_with("auto");
  ASSERT_TRUE(drift.noise.has_value()) << drift.noise_choice;
  EXPECT_GT(drift.noise->gm_var, 0.0) << drift.noise_choice;
  // drift_averaging=sigma keeps the mean of the fit without averaging; its covariance is the ridge mixture's
  // second moment about that mean: the mixture's covariance plus s s', s = the mixture's mean - the fit's mean.
  const BayesFit plain = fit_with("auto", "none"), widened = fit_with("auto", "sigma");
  EXPECT_EQ(widened.rbf_weights, plain.rbf_weights);
  EXPECT_EQ(widened.fixed_weights, plain.fixed_weights);
  Eigen::VectorXd shift(plain.rbf_weights.size() + plain.fixed_weights.size());
  shift << drift.rbf_weights - plain.rbf_weights, drift.fixed_weights - plain.fixed_weights;
  ASSERT_GT(shift.norm(), 0.0);  // the ridge's fits differ: the identity below is not trivially met
  EXPECT_LT((widened.covariance - drift.covariance - shift * shift.transpose()).norm(), 1e-8 * widened.covariance.norm());
}

// Coverage of a known truth by the 95 % band, over several seeds (issue 11: the band covers 0.93-0.97).
struct Coverage {
  int inside = 0, total = 0;
  double value() const { return static_cast<double>(inside) / std::max(1, total); }
};

void add_coverage(const BayesFit& fit, const Eigen::MatrixXd& test, const Eigen::VectorXd& truth, Coverage& c) {
  const Eigen::Index m = fit.centres.rows();
  Eigen::MatrixXd h(test.rows(), m + 1);
  h.leftCols(m) = gaussian_columns(test, fit.centres, fit.widths);
  h.col(m).setOnes();
  Eigen::VectorXd weights(m + 1);
  weights << fit.rbf_weights, fit.fixed_weights;
  const Eigen::VectorXd sigma = ((h * fit.covariance).cwiseProduct(h).rowwise().sum().array() + fit.model_error_var).sqrt().matrix();
  const Eigen::VectorXd error = h * weights - truth;
  for (Eigen::Index i = 0; i < test.rows(); ++i, ++c.total) c.inside += std::abs(error(i)) <= 1.96 * sigma(i);
}

TEST(BayesFit, ModelErrorBetweenLevelsIsCoveredByCrossValidation) {
  // Input 0 on 9 levels 0.25 apart, input 1 a ramp; the truth has a ripple of period 0.55 in input 0 (0.45
  // cycles per level, as sensor C's scale-factor ripple on its staircase): planted model error, as no width
  // the level bound allows can follow it. Its alias alternates from level to level, which leaving a level
  // out reveals. (A ripple whose alias is a smooth wave over the levels, e.g. period 0.22, is invisible in
  // the data: nothing can reveal it.) The band, checked halfway between the levels, must cover the truth
  // once cross-validation over the levels has seen the misfit; the posterior alone does not.
  auto truth = [](const Eigen::MatrixXd& x) {
    return (0.8 * x.col(0).array() + 0.4 * (2.0 * x.col(1).array()).sin() + 0.3 * (2 * M_PI * x.col(0).array() / 0.55).cos()).matrix().eval();
  };
  Eigen::MatrixXd mid(8 * 21, 2);
  for (Eigen::Index i = 0; i < 8; ++i)
    for (Eigen::Index j = 0; j < 21; ++j) mid(i * 21 + j, 0) = -0.875 + 0.25 * static_cast<double>(i), mid(i * 21 + j, 1) = -1 + 0.1 * static_cast<double>(j);
  Coverage with_cv, posterior_only;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const Eigen::Index n = 2400;
    Drawn d;
    d.x.resize(n, 2);
    RandomStream r(seed, "levels-model-error");
    for (Eigen::Index i = 0; i < n; ++i) {
      d.x(i, 0) = -1 + 0.25 * static_cast<double>(((i / 20) * 5) % 9);
      d.x(i, 1) = -1 + 2 * static_cast<double>(i) / static_cast<double>(n - 1);
    }
    d.y = truth(d.x);
    for (Eigen::Index i = 0; i < n; ++i) d.y(i) += 0.1 * r.normal();
    for (const std::string mode : {"cv", "none"}) {
      BayesFitOptions o;
      o.nodes = 60, o.noise = "white", o.model_error = mode;
      SolveMonitor monitor;
      const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
      add_coverage(fit, mid, truth(mid), mode == "cv" ? with_cv : posterior_only);
      if (mode == "cv") {
        EXPECT_GT(fit.model_error_var, 0.0) << fit.model_error_note;
      }
    }
  }
  EXPECT_GT(with_cv.value(), 0.90);
  EXPECT_LT(posterior_only.value(), 0.80);  // the misfit the test plants is real: without the estimate the band misses it
}

TEST(BayesModelError, GroupMeanNoiseCovarianceEqualsTheBruteForceDoubleSum) {
  // Groups of uneven length, some interleaved in time (cells of the input grid revisited) and some with gaps
  // between them, white + Gauss-Markov: the one-sweep sums against cov(mean_r, mean_s) = 1/(n_r n_s)
  // sum_ij (white delta_ij + gm exp(-|t_i - t_j|/tau)) written out.
  NoiseModel m;
  m.dt_s = 0.5, m.white_var = 0.3, m.gm_var = 0.7, m.gm_tau_s = 4.0;
  const std::vector<std::vector<double>> runs = {{0.0, 0.5, 1.0, 6.0, 9.5}, {3.0}, {3.5, 4.0, 4.5, 5.0, 5.5}, {1.5, 7.0, 12.0, 12.5}, {200.0, 200.5}};
  const Eigen::MatrixXd v = group_mean_noise_covariance(runs, m);
  for (std::size_t r = 0; r < runs.size(); ++r)
    for (std::size_t q = 0; q < runs.size(); ++q) {
      double sum = 0.0;
      for (std::size_t i = 0; i < runs[r].size(); ++i)
        for (std::size_t j = 0; j < runs[q].size(); ++j)
          sum += (r == q && i == j ? m.white_var : 0.0) + m.gm_var * std::exp(-std::abs(runs[r][i] - runs[q][j]) / m.gm_tau_s);
      const double expected = sum / static_cast<double>(runs[r].size() * runs[q].size());
      EXPECT_NEAR(v(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(q)), expected, 1e-12 + 1e-12 * std::abs(expected)) << r << ", " << q;
    }
  m.gm_var = 0.0;  // white: the run means are independent, variance white / n
  const Eigen::MatrixXd w = group_mean_noise_covariance(runs, m);
  EXPECT_NEAR(w(2, 2), 0.3 / 5, 1e-15);
  EXPECT_EQ(w(0, 1), 0.0);
}

// Flat-prior physics of the planted-misfit tests: cubic in input 0, quadratic in input 1.
Eigen::MatrixXd polynomial_physics(const Eigen::MatrixXd& x) {
  Eigen::MatrixXd f(x.rows(), 6);
  f.col(0).setOnes();
  f.col(1) = x.col(0), f.col(2) = x.col(0).array().square(), f.col(3) = x.col(0).array().cube();
  f.col(4) = x.col(1), f.col(5) = x.col(1).array().square();
  return f;
}

TEST(BayesFit, ModelErrorGrowingAcrossLevelsIsJudgedByItsNullVarianceNotItsSpread) {
  // Physics alone (no RBF part: flat-prior polynomial columns, cubic in input 0, quadratic in input 1), input
  // 0 on 9 levels 0.25 apart, input 1 a ramp, small noise. The truth adds a ripple of period 0.55 in input 0
  // (0.45 cycles per level) whose amplitude grows as input 0 to the 4th (sensor C's scale-factor ripple grows
  // with the rate on its staircase): the excess differs from level to level by far more than its null
  // variance. The old test - the mean over 2 spreads over the folds - discards it on every seed (excess 0.12
  // +- 0.065; coverage 0.04), as it did on sensor C's staircase at 1 deg/h (coverage 0.0). Between the
  // levels the band must cover the truth and not be grossly wide (rms under 2x the rms error there: a
  // left-out level is predicted at twice the distance). Without the ripple nothing is added.
  auto truth = [](const Eigen::MatrixXd& x, double ripple) {
    return (0.8 * x.col(0).array() + 0.3 * x.col(0).array().cube() + 0.4 * x.col(1).array().square() +
            ripple * x.col(0).array().pow(4) * (2 * M_PI * x.col(0).array() / 0.55).cos()).matrix().eval();
  };
  const auto physics = polynomial_physics;
  // Held-out points between the levels (1/8 .. 7/8 of the spacing), as a held-out trajectory crosses them.
  Eigen::MatrixXd mid(8 * 7 * 11, 2);
  for (Eigen::Index i = 0, row = 0; i < 8; ++i)
    for (Eigen::Index k = 1; k < 8; ++k)
      for (Eigen::Index j = 0; j < 11; ++j, ++row) mid(row, 0) = -1 + 0.25 * static_cast<double>(i) + 0.25 * static_cast<double>(k) / 8, mid(row, 1) = -1 + 0.2 * static_cast<double>(j);
  Coverage c;
  double sigma2 = 0.0, error2 = 0.0;
  int added_without_ripple = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    for (const double ripple : {0.6, 0.0}) {
      const Eigen::Index n = 2400;
      BayesProblem p;
      p.x.resize(n, 2);
      RandomStream r(seed, "levels-growing-model-error");
      for (Eigen::Index i = 0; i < n; ++i) {
        p.x(i, 0) = -1 + 0.25 * static_cast<double>(((i / 20) * 5) % 9);
        p.x(i, 1) = -1 + 2 * static_cast<double>(i) / static_cast<double>(n - 1);
      }
      p.y = truth(p.x, ripple);
      for (Eigen::Index i = 0; i < n; ++i) p.y(i) += 0.02 * r.normal();
      p.fixed = physics(p.x), p.t_s = unit_times(n);
      BayesFitOptions o;
      o.nodes = 0, o.noise = "white";
      SolveMonitor monitor;
      const BayesFit fit = fit_bayes(p, o, monitor);
      if (ripple == 0.0) {
        added_without_ripple += fit.model_error_excess > 2.0 * fit.model_error_standard_error;  // significant
        continue;
      }
      EXPECT_GT(fit.model_error_var, 0.0) << fit.model_error_note;
      const Eigen::MatrixXd h = physics(mid);
      const Eigen::VectorXd error = h * fit.fixed_weights - truth(mid, ripple);
      const Eigen::VectorXd var = (h * fit.covariance).cwiseProduct(h).rowwise().sum().array() + fit.model_error_var;
      for (Eigen::Index i = 0; i < mid.rows(); ++i, ++c.total) c.inside += std::abs(error(i)) <= 1.96 * std::sqrt(var(i));
      error2 += error.squaredNorm(), sigma2 += var.sum();
    }
  }
  EXPECT_GT(c.value(), 0.85);  // 0.87: a constant s_m^2 under-covers the outer levels, over-covers the inner
  EXPECT_LT(c.value(), 0.99);  // 1.0 with the level fold's full excess (band rms 2.1x the error)
  EXPECT_LT(std::sqrt(sigma2 / error2), 2.0);
  EXPECT_LE(added_without_ripple, 1);
}

// A sine sweep's misfit too small for its runs to resolve: physics alone (flat-prior polynomial columns),
// input 0 a fast sine (a rate cycle), input 1 a slow ramp (a temperature scan), white noise; the truth adds
// a ripple in input 0 that the polynomial cannot follow. Within a time block the rate cycle revisits every
// rate: averaged over cells of the input grid the ripple stands above the noise, averaged over runs (a few
// samples each) it does not. Returns the band's coverage at inputs drawn over the domain and counts the
// fits that added a model error.
Coverage sweep_with_ripple(const std::string& groups, double ripple, int seeds, int& added) {
  auto truth = [ripple](const Eigen::MatrixXd& x) {
    return (0.8 * x.col(0).array() + 0.3 * x.col(0).array().cube() + 0.4 * x.col(1).array().square() +
            ripple * (2 * M_PI * x.col(0).array() / 0.45).cos()).matrix().eval();
  };
  const auto physics = polynomial_physics;
  Coverage c;
  added = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Eigen::Index n = 4000;
    BayesProblem p;
    p.x = sine_and_ramp(n, 41.0, 0.3 * seed);
    p.y = truth(p.x);
    RandomStream r(static_cast<std::uint64_t>(seed), "sweep-ripple");
    for (Eigen::Index i = 0; i < n; ++i) p.y(i) += r.normal();
    p.fixed = physics(p.x), p.t_s = unit_times(n);
    BayesFitOptions o;
    o.nodes = 0, o.noise = "white";
    if (groups == "none") o.model_error = "none"; else o.model_error_groups = groups;
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(p, o, monitor);
    added += fit.model_error_excess > 2.0 * fit.model_error_standard_error;  // the old rule would add
    const Eigen::MatrixXd test = uniform_inputs(400, 900 + static_cast<std::uint64_t>(seed));
    const Eigen::MatrixXd h = physics(test);
    const Eigen::VectorXd error = h * fit.fixed_weights - truth(test);
    const Eigen::VectorXd var = (h * fit.covariance).cwiseProduct(h).rowwise().sum().array() + fit.model_error_var;
    for (Eigen::Index i = 0; i < test.rows(); ++i, ++c.total) c.inside += std::abs(error(i)) <= 1.96 * std::sqrt(var(i));
  }
  return c;
}

// The cross-validated prediction error every model_error=cv fit reports (cv_mse; details cv_rms_dph), against
// an independent brute force: physics alone (flat-prior polynomial columns), white noise, no levelled input, so
// the folds are 10 contiguous time blocks; each block predicted by the least-squares fit of the other nine, and
// the squared residuals averaged over every sample. The figure must be that mean (the fit's 1e-10 prior on the
// flat columns moves it by far less than 1e-6), and above the noise variance (1): a fold extrapolates.
TEST(BayesFit, CrossValidatedErrorIsTheBlocksPredictedFromTheOtherBlocks) {
  const Eigen::Index n = 3000;
  BayesProblem p;
  p.x = sine_and_ramp(n, 37.3);  // no repeated levels
  p.y = (0.8 * p.x.col(0).array() + 0.2 * p.x.col(0).array().cube() + 0.5 * p.x.col(1).array().cube()).matrix();
  RandomStream r(5, "cv-mse");
  for (Eigen::Index i = 0; i < n; ++i) p.y(i) += r.normal();
  p.fixed = polynomial_physics(p.x), p.t_s = unit_times(n);
  BayesFitOptions o;
  o.nodes = 0, o.noise = "white";
  SolveMonitor monitor;
  const BayesFit fit = fit_bayes(p, o, monitor);
  ASSERT_NE(fit.model_error_note.find("10 time blocks"), std::string::npos) << fit.model_error_note;
  double squared = 0.0;
  for (int k = 0; k < 10; ++k) {
    std::vector<Eigen::Index> train, test;
    for (Eigen::Index i = 0; i < n; ++i) (i * 10 / n == k ? test : train).push_back(i);
    Eigen::MatrixXd a(static_cast<Eigen::Index>(train.size()), p.fixed.cols());
    Eigen::VectorXd b(a.rows());
    for (std::size_t j = 0; j < train.size(); ++j) a.row(static_cast<Eigen::Index>(j)) = p.fixed.row(train[j]), b(static_cast<Eigen::Index>(j)) = p.y(train[j]);
    const Eigen::VectorXd w = a.colPivHouseholderQr().solve(b);
    for (const Eigen::Index i : test) squared += std::pow(p.y(i) - p.fixed.row(i).dot(w), 2);
  }
  const double brute = squared / static_cast<double>(n);
  EXPECT_NEAR(fit.cv_mse, brute, 1e-6 * brute);
  EXPECT_GT(brute, 1.0);  // the end blocks extrapolate the input-1 polynomial (the truth's cube, the physics' square)
}

TEST(BayesFit, ModelErrorBelowTwoStandardErrorsStillWidensTheBand) {
  // A ripple the cross-validation resolves at under 2 standard errors on every seed: the old all-or-nothing
  // test added nothing, and the band covered 0.74 of the truth (the posterior alone). The estimate itself,
  // never negative, is added now: 0.867 over 6 x 400 points (binomial sd ~0.007 were they independent) -
  // closer to 0.95, not there: an estimate at 1 standard error is a noisy one.
  int significant = 0, unused = 0;
  const Coverage with_cv = sweep_with_ripple("runs", 0.06, 6, significant);
  const Coverage posterior_only = sweep_with_ripple("none", 0.06, 6, unused);
  EXPECT_LE(significant, 1);
  EXPECT_LT(posterior_only.value(), 0.78);
  EXPECT_GT(with_cv.value(), 0.84);
  EXPECT_GT(with_cv.value(), posterior_only.value() + 0.08);
  EXPECT_LT(with_cv.value(), 0.99);
}

// How many of `reps` fits of data drawn from the prior (30 nodes, white noise) add a model error; every fit's
// note must name the folds `fold_kind`.
int model_error_added_on_prior_draws(Eigen::Index n, int reps, std::uint64_t seed0, int scan, const std::string& fold_kind) {
  int added = 0;
  for (int rep = 0; rep < reps; ++rep) {
    const Drawn d = draw(n, 30, Eigen::RowVector2d(0.3, 0.5), 0.1, seed0 + static_cast<std::uint64_t>(rep));
    BayesFitOptions o;
    o.nodes = 30, o.noise = "white", o.scan = scan;
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
    added += fit.model_error_excess > 2.0 * fit.model_error_standard_error;  // significant
    EXPECT_NE(fit.model_error_note.find(fold_kind), std::string::npos) << fit.model_error_note;
  }
  return added;
}

TEST(BayesFit, ModelErrorIsNotAddedWhenTheModelClassIsRight) {
  // Data drawn from the prior with white noise: cross-validation must find no significant misfit on most
  // seeds (a 2-standard-error test over 10 time blocks), and the band stays where the exact posterior puts it.
  EXPECT_LE(model_error_added_on_prior_draws(1500, 6, 300, 4, "time blocks"), 2);
}

TEST(BayesFit, ModelErrorTestStaysCalibratedWhenEverySampleIsItsOwnRun) {
  // Inputs drawn at random: nearly every sample is its own run, ~2,500 per time block, over the 2,000 the null
  // covariance is formed for; groups of runs stand in. Drawn from the prior with white noise, the test must
  // still add nothing on most seeds.
  EXPECT_LE(model_error_added_on_prior_draws(26000, 3, 700, 3, "time blocks"), 1);
}

TEST(BayesFit, SlowGaussMarkovDriftKeepsTheBandHonest) {
  // Gauss-Markov drift with tau a third of the record, confounded with a smooth function of a slow input
  // (a temperature ramp): its level is barely identified, and the posterior must carry that. Coverage of
  // the noise-free truth at inputs drawn over the domain, over 8 seeds.
  const Eigen::Index n = 1500;
  const double tau = 500.0;
  Coverage c;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    Drawn d;
    d.x = sine_and_ramp(n, 37.0);
    auto truth = [](const Eigen::MatrixXd& x) { return (x.col(0).array() * (1 + 0.5 * x.col(1).array()) + 0.5 * x.col(1).array().square()).matrix().eval(); };
    d.y = truth(d.x);
    RandomStream r(seed, "slow-gm");
    const double phi = std::exp(-1.0 / tau);
    double g = 0.3 * r.normal();
    for (Eigen::Index i = 0; i < n; ++i) {
      g = phi * g + 0.3 * std::sqrt(1 - phi * phi) * r.normal();
      d.y(i) += g + 0.05 * r.normal();
    }
    BayesFitOptions o;
    o.nodes = 40, o.noise = "auto";
    SolveMonitor monitor;
    const BayesFit fit = fit_bayes(problem_of(d), o, monitor);
    ASSERT_TRUE(fit.noise.has_value()) << fit.noise_choice;
    const Eigen::MatrixXd test = uniform_inputs(200, 700 + seed);
    add_coverage(fit, test, truth(test), c);
  }
  EXPECT_GT(c.value(), 0.85);
}

// The 8-h classical soak's inputs are levelled (13 temperature plateaus, a few table rates): every common width
// of the scan leaves the hybrid's network off (alpha at its bound), where the evidence is flat in the widths
// and equals the physics' alone, so the gradient search cannot leave. A narrow temperature and a wide rate
// width carry the misfit the physics leaves; the per-input grid tried on that plateau (bayes_fit.cpp) finds it.
TEST(HybridFit, FindsTheNetworkALevelledSoakSupportsOnlyWithUnequalWidths) {
  const Simulation s = simulate_files("builtin:sensors/open_loop_fog.yaml", "builtin:trajectories/classical_soak.yaml", 1);
  HybridOptions o;
  o.noise = "white";
  SolveSummary with_network, physics_alone;
  fit_hybrid(s.recording, o, with_network);
  o.nodes = 0;
  fit_hybrid(s.recording, o, physics_alone);
  const double gain = with_network.details["log_evidence"].get<double>() - physics_alone.details["log_evidence"].get<double>();
  EXPECT_GT(gain, 3.0);  // 6.6 (log evidence 8397.54 against 8390.97); 0 before the grid
  EXPECT_GT(with_network.details["effective_parameters"].get<double>(), 2.0);
  const auto widths = with_network.details["width"];
  EXPECT_LT(widths[0].get<double>(), 0.5 * widths[1].get<double>()) << widths;
}

// Recordings that do not vary an input, and a table at three rates: the hybrid leaves out exactly the physics
// columns the recording cannot determine (they used to stop the fit: "fixed column k is a combination"), says
// so, and recovers the planted physics it keeps. Planted, deg/h: e = 40 + 8 dT - 3 dT^2 (dT = (T - 20) / 40)
// + 3600 w (300 + 150 u + 80 u^2) ppm, u = w / 100 deg/s, plus 2 deg/h of white noise at 1 Hz.
Recording planted_recording(const std::function<double(double)>& rate_dps, const std::function<double(double)>& temp_c) {
  const int n = 3000;
  RandomStream r(11, "hybrid-left-out");
  std::vector<double> t(n), w(n), temp(n), gyro(n);
  for (int i = 0; i < n; ++i) {
    t[i] = i, w[i] = rate_dps(i), temp[i] = temp_c(i);
    const double dt = (temp[i] - 20.0) / 40.0, u = w[i] / 100.0;
    const double e_dph = 40 + 8 * dt - 3 * dt * dt + 3600 * w[i] * (300 + 150 * u + 80 * u * u) * 1e-6 + 2.0 * r.normal();
    gyro[i] = w[i] + e_dph / 3600.0;
  }
  Recording rec("<planted>");
  rec.set_column("t_s", t), rec.set_column("ref_rate_dps", w), rec.set_column("temp_c", temp), rec.set_column("gyro_dps", gyro);
  return rec;
}

double planted_error_dph(double w_dps, double temp_c) {
  const double dt = (temp_c - 20.0) / 40.0, u = w_dps / 100.0;
  return 40 + 8 * dt - 3 * dt * dt + 3600 * w_dps * (300 + 150 * u + 80 * u * u) * 1e-6;
}

std::vector<std::string> left_out(const SolveSummary& s) {
  if (!s.details.contains("physics_left_out")) return {};
  return s.details["physics_left_out"]["columns"].get<std::vector<std::string>>();
}

TEST(HybridFit, LeavesOutThePhysicsTheRecordingDoesNotDetermine) {
  HybridOptions o;
  o.noise = "white", o.nodes = 0, o.bias_order = 2;
  auto sweep = [](double i) { return 100.0 * std::sin(2 * M_PI * i / 97.0); };
  auto ramp = [](double i) { return -20.0 + 80.0 * i / 2999.0; };
  // A rate table at one temperature: every dT column goes; the rate law at 25 C is recovered.
  SolveSummary s;
  auto m = fit_hybrid(planted_recording(sweep, [](double) { return 25.0; }), o, s);
  EXPECT_EQ(left_out(s), (std::vector<std::string>{"dT^1", "dT^2", "w dT^1 u^0", "w dT^1 u^1", "w dT^1 u^2", "w dT^1 u^3",
                                                    "w dT^2 u^0", "w dT^2 u^1", "w dT^2 u^2", "w dT^2 u^3"}));
  EXPECT_NE(s.details["physics_left_out"]["note"].get<std::string>().find("temperature stays within 0 C of 25 C"), std::string::npos);
  for (double w : {-90.0, -30.0, 0.0, 45.0, 90.0}) {
    EXPECT_NEAR(units::radps_to_dph(m->error_at(units::dps_to_radps(w), 25.0)), planted_error_dph(w, 25.0), 0.3) << w;
  }
  // A thermal soak at rest: every scale-factor column goes; the bias over temperature is recovered.
  m = fit_hybrid(planted_recording([](double) { return 0.0; }, ramp), o, s);
  EXPECT_EQ(left_out(s).size(), 12u);
  EXPECT_EQ(left_out(s).front(), "w dT^0 u^0");
  for (double temp : {-15.0, 10.0, 35.0, 55.0}) EXPECT_NEAR(units::radps_to_dph(m->error_at(0.0, temp)), planted_error_dph(0.0, temp), 0.3) << temp;
  // A table at three rates (0, +-100 deg/s) over a temperature ramp: u^2 and u^3 agree with u^0 and u^1 there.
  m = fit_hybrid(planted_recording([](double i) { return 100.0 * (static_cast<int>(i / 50) % 3 - 1); }, ramp), o, s);
  EXPECT_EQ(left_out(s), (std::vector<std::string>{"w dT^0 u^2", "w dT^0 u^3", "w dT^1 u^2", "w dT^1 u^3", "w dT^2 u^2", "w dT^2 u^3"}));
  for (double w : {-100.0, 0.0, 100.0}) EXPECT_NEAR(units::radps_to_dph(m->error_at(units::dps_to_radps(w), 30.0)), planted_error_dph(w, 30.0), 0.3) << w;
  // A recording that varies both keeps every column.
  fit_hybrid(planted_recording(sweep, ramp), o, s);
  EXPECT_TRUE(left_out(s).empty());
}

}  // namespace
}  // namespace gyrosid
