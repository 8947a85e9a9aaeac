// The design's choice of the hybrid's network by the expected evidence (design/evidence_network.h): the
// expected log evidence against the Bayes solver's own evidence averaged over simulated noise, and planted
// prior scales and widths recovered.
#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cmath>

#include "core/random.h"
#include "design/evidence_network.h"
#include "model/gaussian_node.h"
#include "solvers/bayes/evidence.h"
#include "solvers/common/candidates.h"

namespace gyrosid::design {
namespace {

Eigen::RowVectorXd widths2(double rate, double temperature) { return Eigen::RowVector2d(rate, temperature); }

Eigen::MatrixXd uniform_inputs(Eigen::Index n, RandomStream& r) {
  Eigen::MatrixXd x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) x(i, 0) = 2.0 * r.uniform() - 1.0, x(i, 1) = 2.0 * r.uniform() - 1.0;
  return x;
}

// Projects the columns of m off the span of f (unit white noise: no whitening).
Eigen::MatrixXd project_off(const Eigen::MatrixXd& f, Eigen::MatrixXd m) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(f);
  const Eigen::MatrixXd q = Eigen::MatrixXd(qr.householderQ()).leftCols(f.cols());
  m -= q * (q.transpose() * m);
  return m;
}

TEST(DesignEvidenceNetwork, ExpectedEvidenceIsTheBayesSolversEvidenceAveragedOverTheNoise) {
  // y = y0 + e, e ~ N(0, I); fixed columns [1, x1, x2] with a flat prior, 25 Gaussian nodes. The Bayes solver's
  // log evidence (solvers/bayes/evidence.h, its own projection and eigen-solution) averaged over 3000 noise
  // draws must match the closed form 2 E log p / 2 in its dependence on alpha (the rest is constant).
  RandomStream r(11, "test/expected-evidence");
  const Eigen::Index n = 400;
  const Eigen::MatrixXd x = uniform_inputs(n, r);
  Eigen::MatrixXd f(n, 3);
  f << Eigen::VectorXd::Ones(n), x;
  Eigen::MatrixXd centres(25, 2);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) centres.row(5 * i + j) << -0.8 + 0.4 * i, -0.8 + 0.4 * j;
  const Eigen::MatrixXd phi = gaussian_columns(x, centres, widths2(0.5, 0.5));
  const Eigen::VectorXd y0 = 0.6 * ((2.0 * x.col(0)).array().sin() + 0.5 * x.col(1).array().square()).matrix();
  const ExpectedEvidence ev(project_off(f, phi), project_off(f, y0), static_cast<double>(n - 3));
  const double best = ev.best_log_alpha();
  const std::vector<double> us{best - 2.0, best + 2.0, best + 5.0};
  std::vector<double> sum(us.size(), 0.0), sum2(us.size(), 0.0);
  const int draws = 3000;
  for (int k = 0; k < draws; ++k) {
    Eigen::VectorXd y = y0;
    for (Eigen::Index i = 0; i < n; ++i) y(i) += r.normal();
    const FixedPart fixed(f, y, nullptr);
    Eigen::MatrixXd p = phi;
    fixed.project(p);
    const RbfEvidence bayes(p, fixed);
    const double at_best = bayes.log_evidence({best, 0.0});
    for (std::size_t j = 0; j < us.size(); ++j) {
      const double d = bayes.log_evidence({us[j], 0.0}) - at_best;
      sum[j] += d, sum2[j] += d * d;
    }
  }
  for (std::size_t j = 0; j < us.size(); ++j) {
    const double mean = sum[j] / draws, se = std::sqrt((sum2[j] / draws - mean * mean) / draws);
    const double expected = 0.5 * (ev.at(us[j]) - ev.at(best));
    EXPECT_LT(expected, 0.0) << "best_log_alpha is not the maximum, at " << us[j] - best;
    EXPECT_NEAR(mean, expected, 4.0 * se + 1e-3) << "log alpha offset " << us[j] - best;
    EXPECT_LT(se, 0.1 * std::abs(expected)) << "the Monte Carlo check is not decisive";
  }
}

TEST(DesignEvidenceNetwork, APlantedPriorScaleIsRecovered) {
  // y0 = Phi w with w ~ N(0, s^2): the expected evidence's alpha must give back s (per informed direction the
  // optimum prior variance is b^2 / lambda, whose mean is s^2); unit white noise, a constant fixed column.
  RandomStream r(12, "test/planted-prior");
  const Eigen::Index n = 3000;
  const Eigen::MatrixXd x = uniform_inputs(n, r);
  const Eigen::MatrixXd centres = rows_of(x, select_candidates(x, 80));
  const Eigen::MatrixXd phi = gaussian_columns(x, centres, widths2(0.3, 0.3));
  for (double s : {0.5, 2.0}) {
    Eigen::VectorXd w(centres.rows());
    for (Eigen::Index j = 0; j < w.size(); ++j) w(j) = s * r.normal();
    const Eigen::MatrixXd f = Eigen::VectorXd::Ones(n);
    const ExpectedEvidence ev(project_off(f, phi), project_off(f, phi * w), static_cast<double>(n - 1));
    const double u = ev.best_log_alpha();
    EXPECT_NEAR(std::exp(-0.5 * u) / s, 1.0, 0.3) << s;
    EXPECT_GT(ev.gamma(u), 20.0);
    EXPECT_LT(ev.gamma(u), 80.0);
  }
}

TEST(DesignEvidenceNetwork, PlantedWidthsAndPriorAreRecoveredFromTheNoiseFreeTarget) {
  // A smooth error made of 40 Gaussian nodes with widths (0.25, 0.7) in the range-normalised inputs, observed
  // at 1 Hz with white noise: the search (a common-width scan, then per-input widths) must find those widths
  // though its own centres are elsewhere, and a network whose prior is set by their evidence.
  RandomStream r(13, "test/planted-widths");
  const Eigen::Index n = 2500;
  Observations o;
  o.inputs.t_s.resize(static_cast<std::size_t>(n));
  o.inputs.rate.resize(n), o.inputs.temp_c.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    o.inputs.t_s[static_cast<std::size_t>(i)] = static_cast<double>(i);
    o.inputs.rate(i) = 1.5 * (2.0 * r.uniform() - 1.0);          // rad/s, range [-1.5, 1.5]
    o.inputs.temp_c(i) = 10.0 + 30.0 * (2.0 * r.uniform() - 1.0);  // deg C, range [-20, 40]
  }
  Eigen::MatrixXd x(n, 2);
  x.col(0) = o.inputs.rate / 1.5, x.col(1) = (o.inputs.temp_c.array() - 10.0) / 30.0;
  Eigen::MatrixXd planted = uniform_inputs(40, r);
  Eigen::VectorXd w(40);
  for (Eigen::Index j = 0; j < 40; ++j) w(j) = 2e-5 * r.normal();  // rad/s (4 deg/h)
  o.true_error = gaussian_columns(x, planted, widths2(0.25, 0.7)) * w;
  o.weight_s = Eigen::VectorXd::Ones(n);
  NoiseSpec noise;
  noise.white_psd = std::pow(5e-6, 2);  // 1 deg/h at 1 Hz
  const Eigen::MatrixXd physics = Eigen::VectorXd::Ones(n);
  const NetworkNodes net = expected_evidence_network(o, physics, noise, NetworkSearchOptions{});
  EXPECT_NEAR(net.offset(1), o.inputs.temp_c.minCoeff() / 2 + o.inputs.temp_c.maxCoeff() / 2, 1e-12);
  EXPECT_EQ(net.centres.rows(), 200);
  EXPECT_NEAR(net.widths(0) / 0.25, 1.0, 0.25);
  EXPECT_NEAR(net.widths(1) / 0.7, 1.0, 0.25);
  EXPECT_GT(net.effective_parameters, 10.0);
  // The network's columns at the observations are the search's (same normalisation and centres).
  Eigen::MatrixXd xn(n, 2);
  xn.col(0) = (o.inputs.rate.array() - 0.5 * (o.inputs.rate.maxCoeff() + o.inputs.rate.minCoeff())) / (0.5 * (o.inputs.rate.maxCoeff() - o.inputs.rate.minCoeff()));
  xn.col(1) = (o.inputs.temp_c.array() - net.offset(1)) / (0.5 * (o.inputs.temp_c.maxCoeff() - o.inputs.temp_c.minCoeff()));
  EXPECT_NEAR((net.columns(o.inputs) - gaussian_columns(xn, net.centres, net.widths)).cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(xn.col(0).minCoeff(), -1.0, 1e-12);

  // Hyperparameters given (a fitted calibration's, model.network_widths / network_prior_sd_dph): the found ones
  // give the found network back; a prior 10x narrower leaves fewer effective parameters, and the expected
  // evidence there is lower (the found alpha maximises it at these widths).
  NetworkSearchOptions given;
  given.given_widths = net.widths;
  given.given_prior_sd_radps = net.prior_sd_radps;
  const NetworkNodes same = expected_evidence_network(o, physics, noise, given);
  EXPECT_NEAR(same.effective_parameters, net.effective_parameters, 1e-9 * net.effective_parameters);
  EXPECT_NEAR(same.expected_log_evidence, net.expected_log_evidence, 1e-9 * std::abs(net.expected_log_evidence));
  EXPECT_EQ((same.centres - net.centres).cwiseAbs().maxCoeff(), 0.0);
  given.given_prior_sd_radps = 0.1 * net.prior_sd_radps;
  const NetworkNodes narrow = expected_evidence_network(o, physics, noise, given);
  EXPECT_NEAR(narrow.prior_sd_radps, 0.1 * net.prior_sd_radps, 1e-12 * net.prior_sd_radps);
  EXPECT_LT(narrow.effective_parameters, 0.8 * net.effective_parameters);
  EXPECT_LT(narrow.expected_log_evidence, net.expected_log_evidence);
  given.given_widths = Eigen::RowVectorXd::Constant(3, 0.2);
  EXPECT_FALSE(given.validate().empty());
}

}  // namespace
}  // namespace gyrosid::design
