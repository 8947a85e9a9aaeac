// NIST StRD Gauss1 and Gauss2 (certified nonlinear least-squares problems: two Gaussians on an exponential
// baseline - the RBF node model of the ceres solver, plus a baseline) solved with the ceres back-end's
// analytic Gaussian cost and its Levenberg-Marquardt configuration, from both NIST starting points, to the
// certified values: log relative error >= 6 for every parameter.
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "solvers/ceres/gaussian_sum_cost.h"
#include "solvers/log_relative_error.h"

namespace gyrosid {
namespace {

struct NistProblem {
  Eigen::VectorXd x, y;
  std::vector<double> certified;
  std::vector<std::vector<double>> starts;
};

NistProblem load(const std::string& name) {
  std::ifstream in(std::string(GYROSID_TEST_DATA) + "/nist/" + name + ".dat");
  NistProblem p;
  std::vector<double> xs, ys;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    if (line.rfind("# certified:", 0) == 0 || line.rfind("# start:", 0) == 0) {
      std::string hash, tag;
      s >> hash >> tag;
      std::vector<double> v;
      double d;
      while (s >> d) v.push_back(d);
      if (tag == "certified:") p.certified = v;
      else p.starts.push_back(v);
    } else if (!line.empty() && line[0] != '#') {
      double a, b;
      s >> a >> b;
      xs.push_back(a), ys.push_back(b);
    }
  }
  p.x = Eigen::Map<Eigen::VectorXd>(xs.data(), static_cast<Eigen::Index>(xs.size()));
  p.y = Eigen::Map<Eigen::VectorXd>(ys.data(), static_cast<Eigen::Index>(ys.size()));
  return p;
}

using testing_support::lre;

void solve_and_check(const std::string& name) {
  const NistProblem p = load(name);
  ASSERT_EQ(p.x.size(), 250);
  ASSERT_EQ(p.certified.size(), 8u);
  // b1 exp(-b2 x) as the baseline; nodes [c, log r, w] = [b4, log b5, b3] and [b7, log b8, b6].
  const Baseline exponential{2, [](const double* x, const double* b, double* g) {
                               const double e = std::exp(-b[1] * x[0]);
                               if (g) g[0] = e, g[1] = -b[0] * x[0] * e;
                               return b[0] * e;
                             }};
  for (std::size_t s = 0; s < p.starts.size(); ++s) {
    const auto& b = p.starts[s];
    double base[2] = {b[0], b[1]};
    double node1[3] = {b[3], std::log(b[4]), b[2]};
    double node2[3] = {b[6], std::log(b[7]), b[5]};
    ceres::Problem problem;
    problem.AddResidualBlock(new GaussianSumCost(p.x, p.y, 2, &exponential), nullptr, node1, node2, base);
    ceres::Solver::Options o;
    o.linear_solver_type = ceres::DENSE_QR;
    o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    o.max_num_iterations = 1000;
    o.function_tolerance = 1e-15;
    o.gradient_tolerance = 1e-15;
    o.parameter_tolerance = 1e-15;
    ceres::Solver::Summary summary;
    ceres::Solve(o, &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
    const double est[8] = {base[0], base[1], node1[2], node1[0], std::exp(node1[1]), node2[2], node2[0], std::exp(node2[1])};
    for (int k = 0; k < 8; ++k) {
      EXPECT_GE(lre(est[k], p.certified[static_cast<std::size_t>(k)]), 6.0)
          << name << " start " << s + 1 << " b" << k + 1 << " = " << est[k] << " certified " << p.certified[static_cast<std::size_t>(k)];
    }
  }
}

TEST(NistStrd, Gauss1ToCertifiedValues) { solve_and_check("gauss1"); }
TEST(NistStrd, Gauss2ToCertifiedValues) { solve_and_check("gauss2"); }

}  // namespace
}  // namespace gyrosid
