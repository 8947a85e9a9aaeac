// The covariance of overlapping Allan-variance estimates: against its closed form for white noise at the
// shortest tau, and against Monte Carlo for a composite of every exactly realisable process.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

#include "core/random.h"
#include "core/units.h"
#include "noise/allan.h"
#include "noise/allan_covariance.h"
#include "noise/processes.h"

namespace gyrosid {
namespace {

TEST(AllanCovariance, WhiteNoiseAtTheShortestTauHasItsClosedForm) {
  // m = 1: d_k = dt (y_{k+1} - y_k), var 2 s^2 dt^2, lag-1 covariance -s^2 dt^2, so with K = n - 1 terms
  // Var(s_1) / s_1^2 = (3K - 1) / K^2 exactly.
  const double dt = 0.5, sigma = 3.0;  // per-sample sigma
  CompositeNoise white;
  white.white = sigma * std::sqrt(dt);
  for (std::size_t n : {10u, 1000u, 100000u}) {
    const std::vector<std::size_t> m = {1};
    const Eigen::MatrixXd cov = allan_variance_covariance(white, m, n, dt);
    const double k = static_cast<double>(n - 1), s1 = sigma * sigma;
    EXPECT_NEAR(cov(0, 0) / (s1 * s1), (3 * k - 1) / (k * k), 1e-9 * (3 * k - 1) / (k * k)) << n;
  }
}

TEST(AllanCovariance, MatchesMonteCarloForAComposite) {
  // White + quantization + random walk + two Gauss-Markov + ramp, 600 records of 2048 samples.
  const double dt = 1.0;
  const std::size_t n = 2048, runs = 600;
  CompositeNoise model;
  model.white = 3.0, model.quantization = 0.8, model.random_walk = 0.01, model.ramp = 2e-4;
  model.gauss_markov = {{1.5, 4.0}, {0.8, 60.0}};
  NoiseOptions sim;  // the same processes as the generator draws them (rate unit: "rad/s" here is just u)
  sim.arw_rad_rt_s = model.white, sim.rrw_rad_s_rt_s = model.random_walk, sim.rate_ramp_radps2 = model.ramp;
  for (const auto& gm : model.gauss_markov) sim.gauss_markov.push_back({gm.sigma, gm.tau_s});
  const std::vector<std::size_t> ms = {1, 2, 4, 8, 16, 32, 64, 128};
  Eigen::MatrixXd samples(static_cast<Eigen::Index>(runs), static_cast<Eigen::Index>(ms.size()));
  for (std::size_t r = 0; r < runs; ++r) {
    NoiseGenerator g(sim, 1000 + r, "mc");
    RandomStream phase_noise(2000 + r, "quantization");
    std::vector<double> y(n);
    double e_prev = model.quantization * phase_noise.normal();
    for (std::size_t k = 0; k < n; ++k) {
      const double e = model.quantization * phase_noise.normal();  // white angle noise: rate (e_k+1 - e_k) / dt
      y[k] = g.next(static_cast<double>(k) * dt, dt) + (e - e_prev) / dt;
      e_prev = e;
    }
    const AllanPhase phase(y, dt);
    for (std::size_t j = 0; j < ms.size(); ++j) samples(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j)) = phase.variance(ms[j]);
  }
  const Eigen::RowVectorXd mean = samples.colwise().mean();
  const Eigen::MatrixXd centred = samples.rowwise() - mean;
  const Eigen::MatrixXd empirical = centred.transpose() * centred / static_cast<double>(runs - 1);
  const Eigen::MatrixXd cov = allan_variance_covariance(model, ms, n, dt);
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const double tau = static_cast<double>(ms[j]) * dt;
    // The mean is the model's Allan variance (the ramp's mean phase curvature included).
    EXPECT_NEAR(mean(jj), model.allan_variance(tau), 4.0 * std::sqrt(cov(jj, jj) / runs)) << tau;
    // A sample variance from 600 runs of chi-square-like estimates: about 6-12 % relative spread.
    EXPECT_NEAR(empirical(jj, jj) / cov(jj, jj), 1.0, 0.3) << tau;
    for (std::size_t i = 0; i < j; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      const double rho_model = cov(ii, jj) / std::sqrt(cov(ii, ii) * cov(jj, jj));
      const double rho_mc = empirical(ii, jj) / std::sqrt(empirical(ii, ii) * empirical(jj, jj));
      EXPECT_NEAR(rho_mc, rho_model, 0.12) << ms[i] << " x " << ms[j];
    }
  }
}

TEST(AllanCovariance, FlickerTailIsFiniteAndPositiveDefinite) {
  CompositeNoise model;
  model.white = 1.0, model.flicker = 0.3;
  const std::vector<std::size_t> ms = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
  const Eigen::MatrixXd cov = allan_variance_covariance(model, ms, 20000, 0.1);
  EXPECT_TRUE(cov.allFinite());
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  EXPECT_EQ(llt.info(), Eigen::Success);
  // Relative variances grow with tau as the number of independent clusters falls.
  for (Eigen::Index j = 1; j < cov.rows(); ++j) {
    const double tau = static_cast<double>(ms[static_cast<std::size_t>(j)]) * 0.1, prev = tau / 2;
    EXPECT_GT(cov(j, j) / std::pow(model.allan_variance(tau), 2), cov(j - 1, j - 1) / std::pow(model.allan_variance(prev), 2));
  }
}

}  // namespace
}  // namespace gyrosid
