// The three optimisation back-ends are linked and work: one tiny solve each with a known answer.
#include <gtest/gtest.h>

#include <ceres/ceres.h>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>
#include <nlopt.hpp>

#include <cmath>

namespace {

// Ceres: y = exp(m x + c) fitted to noise-free data with analytic derivatives; must return m, c exactly.
struct ExpResidual : public ceres::SizedCostFunction<1, 2> {
  ExpResidual(double x, double y) : x_(x), y_(y) {}
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    const double e = std::exp(p[0][0] * x_ + p[0][1]);
    r[0] = e - y_;
    if (j && j[0]) {
      j[0][0] = x_ * e;
      j[0][1] = e;
    }
    return true;
  }
  double x_, y_;
};

TEST(Backends, CeresFitsAnExponential) {
  double p[2] = {0.0, 0.0};
  ceres::Problem problem;
  for (int i = 0; i < 50; ++i) {
    const double x = 0.1 * i;
    problem.AddResidualBlock(new ExpResidual(x, std::exp(0.3 * x + 0.1)), nullptr, p);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = 1e-15;
  options.parameter_tolerance = 1e-15;
  options.gradient_tolerance = 1e-15;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable());
  EXPECT_NEAR(p[0], 0.3, 1e-9);
  EXPECT_NEAR(p[1], 0.1, 1e-9);
}

// NLopt: Rosenbrock's valley, derivative-free BOBYQA and gradient-based L-BFGS; minimum at (1, 1).
double rosenbrock(const std::vector<double>& x, std::vector<double>& g, void*) {
  const double a = 1 - x[0], b = x[1] - x[0] * x[0];
  if (!g.empty()) {
    g[0] = -2 * a - 400 * x[0] * b;
    g[1] = 200 * b;
  }
  return a * a + 100 * b * b;
}

TEST(Backends, NloptMinimisesRosenbrock) {
  for (auto algorithm : {nlopt::LN_BOBYQA, nlopt::LD_LBFGS}) {
    nlopt::opt opt(algorithm, 2);
    opt.set_min_objective(rosenbrock, nullptr);
    opt.set_xtol_rel(1e-12);
    opt.set_maxeval(20000);
    std::vector<double> x{-1.2, 1.0};
    double f = 0;
    opt.optimize(x, f);
    EXPECT_NEAR(x[0], 1.0, 1e-5) << opt.get_algorithm_name();
    EXPECT_NEAR(x[1], 1.0, 1e-5) << opt.get_algorithm_name();
    EXPECT_LT(f, 1e-10);
  }
}

// Ipopt: Hock & Schittkowski problem 71, min x1 x4 (x1 + x2 + x3) + x3 s.t. x1 x2 x3 x4 >= 25,
// sum x_i^2 = 40, 1 <= x_i <= 5. Published optimum f* = 17.0140173 at (1, 4.7430, 3.8211, 1.3794).
class Hs071 : public Ipopt::TNLP {
 public:
  std::vector<double> solution;
  double objective = 0;

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = 4, m = 2, nnz_jac = 8, nnz_h = 10, style = TNLP::C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index, Ipopt::Number* xl, Ipopt::Number* xu, Ipopt::Index, Ipopt::Number* gl,
                       Ipopt::Number* gu) override {
    for (int i = 0; i < 4; ++i) xl[i] = 1.0, xu[i] = 5.0;
    gl[0] = 25.0, gu[0] = 2e19, gl[1] = gu[1] = 40.0;
    return true;
  }
  bool get_starting_point(Ipopt::Index, bool, Ipopt::Number* x, bool, Ipopt::Number*, Ipopt::Number*, Ipopt::Index,
                          bool, Ipopt::Number*) override {
    x[0] = 1, x[1] = 5, x[2] = 5, x[3] = 1;
    return true;
  }
  bool eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    f = x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2];
    return true;
  }
  bool eval_grad_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number* g) override {
    g[0] = x[3] * (2 * x[0] + x[1] + x[2]);
    g[1] = x[0] * x[3];
    g[2] = x[0] * x[3] + 1;
    g[3] = x[0] * (x[0] + x[1] + x[2]);
    return true;
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Number* g) override {
    g[0] = x[0] * x[1] * x[2] * x[3];
    g[1] = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3];
    return true;
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index, Ipopt::Index* row,
                  Ipopt::Index* col, Ipopt::Number* v) override {
    if (!v) {
      for (int k = 0; k < 8; ++k) row[k] = k / 4, col[k] = k % 4;
      return true;
    }
    v[0] = x[1] * x[2] * x[3], v[1] = x[0] * x[2] * x[3], v[2] = x[0] * x[1] * x[3], v[3] = x[0] * x[1] * x[2];
    for (int i = 0; i < 4; ++i) v[4 + i] = 2 * x[i];
    return true;
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number s, Ipopt::Index, const Ipopt::Number* l, bool,
              Ipopt::Index, Ipopt::Index* row, Ipopt::Index* col, Ipopt::Number* v) override {
    if (!v) {  // lower triangle, row-wise
      int k = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j <= i; ++j) row[k] = i, col[k] = j, ++k;
      return true;
    }
    v[0] = s * 2 * x[3] + l[1] * 2;                                   // (0,0)
    v[1] = s * x[3] + l[0] * x[2] * x[3];                             // (1,0)
    v[2] = l[1] * 2;                                                  // (1,1)
    v[3] = s * x[3] + l[0] * x[1] * x[3];                             // (2,0)
    v[4] = l[0] * x[0] * x[3];                                        // (2,1)
    v[5] = l[1] * 2;                                                  // (2,2)
    v[6] = s * (2 * x[0] + x[1] + x[2]) + l[0] * x[1] * x[2];         // (3,0)
    v[7] = s * x[0] + l[0] * x[0] * x[2];                             // (3,1)
    v[8] = s * x[0] + l[0] * x[0] * x[1];                             // (3,2)
    v[9] = l[1] * 2;                                                  // (3,3)
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*,
                         Ipopt::Number f, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    solution.assign(x, x + n);
    objective = f;
  }
};

TEST(Backends, IpoptSolvesHockSchittkowski71) {
  Ipopt::SmartPtr<Hs071> nlp = new Hs071();
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", 1e-10);
  ASSERT_EQ(app->Initialize(), Ipopt::Solve_Succeeded);
  ASSERT_EQ(app->OptimizeTNLP(nlp), Ipopt::Solve_Succeeded);
  EXPECT_NEAR(nlp->objective, 17.0140173, 1e-6);
  EXPECT_NEAR(nlp->solution[0], 1.0, 1e-6);
  EXPECT_NEAR(nlp->solution[1], 4.7429994, 1e-6);
  EXPECT_NEAR(nlp->solution[2], 3.8211503, 1e-6);
  EXPECT_NEAR(nlp->solution[3], 1.3794082, 1e-6);
}

}  // namespace
