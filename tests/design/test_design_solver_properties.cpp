// One property suite run over every registered design solver (design/design_solver.h's registry, the
// test binary's toy included): its defaults are valid, unknown options are refused listing the known ones,
// a solve on the small problem keeps the limits and the budget, improves on its start by a real margin,
// reports the objective of what it returns, and gives the same programme for the same seed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "design/design_solver.h"
#include "error_of.h"
#include "small_design_problem.h"
#include "trajectory/programme.h"

namespace gyrosid::design {
namespace {

using fixtures::SmallProblem;
using testing_support::error_of;

// Options that keep each solver quick on the small problem (the defaults are for real designs).
OptionMap quick_options(const std::string& solver) {
  if (solver == "nlopt") return {{"global_evaluations", "150"}, {"local_evaluations", "100"}};
  if (solver == "ipopt") return {{"max_iterations", "20"}};
  return {};
}

class DesignSolverProperties : public ::testing::TestWithParam<std::string> {};

TEST_P(DesignSolverProperties, DefaultsAreValidAndUnknownOptionsAreRefused) {
  EXPECT_NO_THROW(make_design_solver(GetParam(), {}, 1));
  EXPECT_THAT(design_solvers().at(GetParam()).help(), ::testing::StartsWith(GetParam() + " - "));
  EXPECT_THAT(error_of([&] { make_design_solver(GetParam(), {{"no_such_option", "1"}}, 1); }),
              ::testing::HasSubstr("unknown option 'no_such_option'; known: "));
}

TEST_P(DesignSolverProperties, ImprovesOnItsStartWithinTheLimitsDeterministically) {
  const std::string& name = GetParam();
  const SmallProblem small;
  const double start = small.problem.objective(small.space.initial());
  std::string first;
  for (int repeat = 0; repeat < 2; ++repeat) {
    auto solver = make_design_solver(name, quick_options(name), 3);
    TableProfile best = small.space.initial();
    const SolveSummary s = run_design_solver(*solver, small.problem, best);
    EXPECT_TRUE(s.usable()) << s.message;
    EXPECT_EQ(s.solver, name);
    EXPECT_GT(s.iterations, 0);
    EXPECT_EQ(best.check_limits(), "");
    EXPECT_NEAR(best.duration_min(), 20.0, 1e-9);
    const double value = small.problem.objective(best);
    EXPECT_LT(value, start - 0.05);  // a real improvement in log variance
    EXPECT_DOUBLE_EQ(s.details["objective"].get<double>(), value);
    TrajectorySpec spec;
    spec.profile = best;
    spec.sampling.rate_hz = 1;
    if (repeat == 0) first = programme_yaml(spec);
    else EXPECT_EQ(programme_yaml(spec), first) << "same seed, same design";
  }
}

INSTANTIATE_TEST_SUITE_P(EveryDesignSolver, DesignSolverProperties, ::testing::ValuesIn(design_solvers().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(DesignSolvers, BadNamesAndOptionsAreNamed) {
  EXPECT_THAT(error_of([] { make_design_solver("cmaes", {}, 1); }), ::testing::HasSubstr("known: nlopt, ipopt"));
  EXPECT_THAT(error_of([] { make_design_solver("nlopt", {{"global", "LD_MMA"}}, 1); }), ::testing::HasSubstr("'global' = 'LD_MMA'"));
  EXPECT_THAT(error_of([] { make_design_solver("ipopt", {{"max_iter", "3"}}, 1); }), ::testing::HasSubstr("unknown option 'max_iter'"));
}

}  // namespace
}  // namespace gyrosid::design
