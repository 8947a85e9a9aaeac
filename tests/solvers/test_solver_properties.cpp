// One property suite run over every registered RBF solver (solvers/solver.h's registry): its defaults are
// valid, unknown options are refused listing the known ones, a solve on a planted problem is usable and
// reduces the error, the summary counts what the cost history holds, and the result is bit-identical for
// the same inputs. The shared Gaussian node's analytic gradient is checked against automatic
// differentiation on ceres::Jet.
#include <ceres/jet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/random.h"
#include "error_of.h"
#include "model/gaussian_node.h"
#include "planted_problem.h"
#include "solvers/solver.h"

namespace gyrosid {
namespace {

using testing_support::planted_problem;

// Options that keep each solver quick on the 441-sample planted problem (the defaults are for recordings).
OptionMap quick_options(const std::string& solver) {
  if (solver == "ceres") return {{"max_iterations", "20"}, {"init.max_nodes", "8"}};
  if (solver == "ipopt") return {{"max_iterations", "20"}, {"nodes", "8"}};
  if (solver == "ofs_loo") return {{"max_nodes", "8"}};
  if (solver == "nlopt") return {{"evaluations", "20"}};
  return {};
}

class RbfSolverProperties : public ::testing::TestWithParam<std::string> {};

TEST_P(RbfSolverProperties, DefaultsAreValidAndHelpListsEveryOption) {
  EXPECT_NO_THROW(make_solver(GetParam(), {}));
  const std::string help = solver_help(GetParam());
  EXPECT_THAT(help, ::testing::StartsWith(GetParam() + " - "));
  EXPECT_THAT(testing_support::error_of([&] { make_solver(GetParam(), {{"no_such_option", "1"}}); }),
              ::testing::HasSubstr("unknown option 'no_such_option'; known: "));
}

TEST_P(RbfSolverProperties, SolveIsUsableCountedAndDeterministic) {
  const RbfProblem p = planted_problem();
  RbfNetwork a = p.empty_network(), b = p.empty_network();
  const SolveSummary s = train(*make_solver(GetParam(), quick_options(GetParam())), p, a);
  train(*make_solver(GetParam(), quick_options(GetParam())), p, b);
  EXPECT_TRUE(s.usable()) << s.message;
  EXPECT_EQ(s.solver, GetParam());
  EXPECT_GE(s.iterations, 1);
  EXPECT_EQ(s.iterations, static_cast<int>(s.cost_history.size()));
  EXPECT_EQ(s.details.at("nodes").get<Eigen::Index>(), a.nodes());
  EXPECT_GT(s.time_s, 0.0);
  EXPECT_GT(s.peak_rss_mb, 0.0);
  // The fit explains most of the planted signal (every solver, even with the quick options).
  const Eigen::VectorXd fitted = a.basis(p.x) * a.weights + Eigen::VectorXd::Constant(p.size(), a.bias);
  EXPECT_LT((fitted - p.y).norm(), 0.05 * p.y.norm());
  // Same inputs, same network, bit for bit.
  EXPECT_EQ(a.centres, b.centres);
  EXPECT_EQ(a.widths, b.widths);
  EXPECT_EQ(a.weights, b.weights);
}

INSTANTIATE_TEST_SUITE_P(EverySolver, RbfSolverProperties, ::testing::ValuesIn(solver_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// node_output's analytic gradient (used by ceres, ipopt and variable projection) against forward-mode
// automatic differentiation of the templated gaussian() on ceres::Jet.
TEST(GaussianNode, AnalyticGradientEqualsAutomaticDifferentiation) {
  using Jet = ceres::Jet<double, 7>;  // d = 3: three centres, three log widths, one weight
  RandomStream r(11, "gaussian-node");
  for (int trial = 0; trial < 50; ++trial) {
    const double x[3] = {r.normal(), r.normal(), r.normal()};
    double block[7];
    for (double& v : block) v = 0.5 * r.normal();
    Jet c[3], width[3], w(block[6], 6);
    for (int k = 0; k < 3; ++k) {
      c[k] = Jet(block[k], k);
      width[k] = exp(Jet(block[3 + k], 3 + k));
    }
    const Jet value = w * gaussian(x, c, width, 3);
    double grad[7];
    const double analytic = node_output(x, {block, 3}, grad);
    EXPECT_NEAR(analytic, value.a, 1e-15);
    for (int k = 0; k < 7; ++k) EXPECT_NEAR(grad[k], value.v[k], 1e-12 * (1 + std::abs(value.v[k]))) << "trial " << trial << ", parameter " << k;
  }
}

}  // namespace
}  // namespace gyrosid
