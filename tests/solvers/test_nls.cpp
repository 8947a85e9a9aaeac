// The generic nonlinear least-squares layer (solvers/nls): NIST StRD Gauss1 posed once with automatic
// derivatives and solved by every registered back-end to the certified values; covariance against an
// independent QR computation on a planted linear problem; observability of a duplicated column; fixed
// entries and bounds honoured.
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <Eigen/QR>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/random.h"
#include "solvers/nls/nls_covariance.h"
#include "solvers/nls/nls_solver.h"
#include "solvers/log_relative_error.h"

namespace gyrosid {
namespace {

struct Gauss1 {
  std::vector<double> x, y, certified;
  std::vector<std::vector<double>> starts;
};

Gauss1 load_gauss1() {
  std::ifstream in(std::string(GYROSID_TEST_DATA) + "/nist/gauss1.dat");
  Gauss1 p;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    if (line.rfind("# certified:", 0) == 0 || line.rfind("# start:", 0) == 0) {
      std::string hash, tag;
      s >> hash >> tag;
      std::vector<double> v;
      for (double d; s >> d;) v.push_back(d);
      (tag == "certified:" ? p.certified : p.starts.emplace_back()) = v;
    } else if (!line.empty() && line[0] != '#') {
      double a, b;
      s >> a >> b;
      p.x.push_back(a), p.y.push_back(b);
    }
  }
  return p;
}

// y = b1 exp(-b2 x) + b3 exp(-(x - b4)^2 / b5^2) + b6 exp(-(x - b7)^2 / b8^2), one residual per sample,
// derivatives by ceres::Jet.
struct Gauss1Residual {
  double x, y;
  template <typename T>
  bool operator()(const T* b, T* r) const {
    using std::exp;
    const T d1 = (x - b[3]) / b[4], d2 = (x - b[6]) / b[7];
    r[0] = b[0] * exp(-b[1] * x) + b[2] * exp(-d1 * d1) + b[5] * exp(-d2 * d2) - y;
    return true;
  }
};

NlsProblem gauss1_problem(const Gauss1& g, const std::vector<double>& start) {
  NlsProblem p;
  const int b = p.add_block("b", start);
  for (std::size_t i = 0; i < g.x.size(); ++i) {
    p.add_residual(std::make_unique<ceres::AutoDiffCostFunction<Gauss1Residual, 1, 8>>(new Gauss1Residual{g.x[i], g.y[i]}), {b});
  }
  return p;
}

using testing_support::lre;

TEST(Nls, EveryBackEndSolvesNistGauss1ToTheCertifiedValues) {
  const Gauss1 g = load_gauss1();
  ASSERT_EQ(g.x.size(), 250u);
  for (const std::string& name : nls_solvers().names()) {
    for (const auto& start : g.starts) {
      NlsProblem p = gauss1_problem(g, start);
      OptionMap options;
      if (name == "nlopt") options = {{"max_evaluations", "20000"}};
      const SolveSummary s = solve(*make_nls_solver(name, options), p);
      EXPECT_TRUE(s.usable()) << name << ": " << s.message;
      for (int k = 0; k < 8; ++k) {
        EXPECT_GE(lre(p.block(0).values[static_cast<std::size_t>(k)], g.certified[static_cast<std::size_t>(k)]), 5.0)
            << name << " b" << k + 1 << " from start " << start[0];
      }
      EXPECT_NEAR(2.0 * s.details["cost"].get<double>(), 1.3158222432e3, 1e-5 * 1.3158222432e3) << name;
      EXPECT_GE(s.iterations, 1) << name;
    }
  }
}

// y_i = A_i theta + noise, blocks: theta_0..1 in one block, theta_2 in another; group 0 only.
class LinearCost : public ceres::SizedCostFunction<1, 2, 1> {
 public:
  LinearCost(Eigen::RowVector3d a, double y) : a_(a), y_(y) {}
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    r[0] = a_(0) * p[0][0] + a_(1) * p[0][1] + a_(2) * p[1][0] - y_;
    if (j) {
      if (j[0]) j[0][0] = a_(0), j[0][1] = a_(1);
      if (j[1]) j[1][0] = a_(2);
    }
    return true;
  }

 private:
  Eigen::RowVector3d a_;
  double y_;
};

TEST(Nls, CovarianceEqualsTheLeastSquaresCovarianceFromAnIndependentQr) {
  RandomStream random(5, "nls/linear");
  const int n = 400;
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd y(n);
  const Eigen::Vector3d truth(1.5, -0.25, 3.0);
  NlsProblem p;
  const int b01 = p.add_block("ab", {0, 0}), b2 = p.add_block("c", {0});
  for (int i = 0; i < n; ++i) {
    const double t = 0.01 * i;
    a.row(i) << 1.0, t, std::sin(3 * t);
    y(i) = a.row(i) * truth + 0.05 * random.normal();
    p.add_residual(std::make_unique<LinearCost>(a.row(i), y(i)), {b01, b2});
  }
  const SolveSummary s = solve(*make_nls_solver("ceres", {}), p);
  ASSERT_TRUE(s.usable());
  // Independent: theta = R^-1 Q'y, s^2 = |r|^2/(n-3), C = s^2 (R'R)^-1.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::Vector3d theta = qr.solve(y);
  const double s2 = (y - a * theta).squaredNorm() / (n - 3);
  const Eigen::Matrix3d r = qr.matrixQR().topRows(3).triangularView<Eigen::Upper>();
  const Eigen::Matrix3d rinv = r.inverse();
  const Eigen::Matrix3d c = s2 * rinv * rinv.transpose();
  EXPECT_NEAR(p.block(b01).values[0], theta(0), 1e-10);
  EXPECT_NEAR(p.block(b2).values[0], theta(2), 1e-10);
  const NlsCovariance cov = estimate_covariance(p);
  ASSERT_TRUE(cov.ok) << cov.message;
  EXPECT_NEAR(cov.group_sigma[0], std::sqrt(s2), 1e-12);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(cov.covariance(i, j), c(i, j), 1e-9 * std::sqrt(c(i, i) * c(j, j))) << i << j;
  for (int i = 0; i < 3; ++i) EXPECT_GE(cov.inflation(i), 1.0 - 1e-9);
}

// Ceres orders a covariance's columns by the parameter blocks' addresses; the estimate must not follow them:
// the same problem with its blocks' storage in the opposite address order gives the same bits (before the fix
// a triad fit's sigmas moved in their last digit with the allocator's settings).
TEST(Nls, CovarianceDoesNotDependOnWhereTheBlocksLiveInMemory) {
  RandomStream random(7, "nls/addresses");
  NlsProblem p;
  const int b01 = p.add_block("ab", {0, 0}), b2 = p.add_block("c", {0});
  for (int i = 0; i < 400; ++i) {
    const double t = 0.01 * i;
    const Eigen::RowVector3d a(1.0, t, std::sin(3 * t));
    p.add_residual(std::make_unique<LinearCost>(a, a * Eigen::Vector3d(1.5, -0.25, 3.0) + 0.05 * random.normal()), {b01, b2});
  }
  ASSERT_TRUE(solve(*make_nls_solver("ceres", {}), p).usable());
  const auto ab_first = [&] { return p.block(b01).values.data() < p.block(b2).values.data(); };
  const NlsCovariance one = estimate_covariance(p);
  // The same values in fresh storage, in the other address order: two candidates each, keep the pair that flips.
  const bool before = ab_first();
  std::vector<std::vector<double>> spare;
  for (int attempt = 0; attempt < 8 && ab_first() == before; ++attempt) {
    std::vector<double> ab = p.block(b01).values, c = p.block(b2).values;
    spare.push_back(std::move(p.block(b01).values)), spare.push_back(std::move(p.block(b2).values));
    if (attempt % 2 == 0) p.block(b2).values = c, p.block(b01).values = ab;
    else p.block(b01).values = ab, p.block(b2).values = c;
  }
  ASSERT_NE(ab_first(), before) << "could not place the blocks in the other address order";
  const NlsCovariance two = estimate_covariance(p);
  ASSERT_TRUE(one.ok && two.ok);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(one.sigma(i), two.sigma(i)) << i;
    for (int j = 0; j < 3; ++j) EXPECT_EQ(one.covariance(i, j), two.covariance(i, j)) << i << j;
  }
}

TEST(Nls, ADuplicatedColumnIsUnobservableAndLaterEntriesYieldToEarlierOnes) {
  NlsProblem p;
  const int b01 = p.add_block("ab", {0, 0}), b2 = p.add_block("c", {0});
  for (int i = 0; i < 50; ++i) {
    const double t = 0.1 * i;
    p.add_residual(std::make_unique<LinearCost>(Eigen::RowVector3d(1.0, t, 2.0), 1.0 + t), {b01, b2});  // c duplicates a
  }
  NlsObservability o = analyse_observability(p);
  EXPECT_TRUE(o.observable[0]);
  EXPECT_TRUE(o.observable[1]);
  EXPECT_FALSE(o.observable[2]);
  EXPECT_EQ(o.rank[0], 2);
  p.fix(b2, 0);  // held at its value: the rest is determined
  o = analyse_observability(p);
  EXPECT_EQ(o.observable.size(), 2u);
  EXPECT_TRUE(o.observable[0] && o.observable[1]);
  for (const std::string& name : nls_solvers().names()) {
    p.block(b01).values = {0, 0};
    solve(*make_nls_solver(name, {}), p);
    EXPECT_NEAR(p.block(b01).values[0], 1.0, 1e-6) << name;
    EXPECT_NEAR(p.block(b01).values[1], 1.0, 1e-6) << name;
    EXPECT_EQ(p.block(b2).values[0], 0.0) << name;
  }
}

TEST(Nls, BoundsAreHonouredByEveryBackEnd) {
  for (const std::string& name : nls_solvers().names()) {
    NlsProblem p;
    const int b01 = p.add_block("ab", {0, 0}), b2 = p.add_block("c", {0});
    for (int i = 0; i < 30; ++i) {
      const double t = 0.1 * i;
      p.add_residual(std::make_unique<LinearCost>(Eigen::RowVector3d(1.0, t, t * t), 2.0 + t), {b01, b2});
    }
    p.set_bounds(b01, {-10, -10}, {1.5, 10});  // the unbounded solution has a = 2
    solve(*make_nls_solver(name, {}), p);
    EXPECT_LE(p.block(b01).values[0], 1.5 + 1e-7) << name;
    EXPECT_NEAR(p.block(b01).values[0], 1.5, 1e-4) << name;
  }
}

TEST(Nls, UnknownSolversAndBadOptionsAreErrorsNamingThem) {
  try {
    make_nls_solver("lbfgs", {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("known: ceres, nlopt, ipopt"), std::string::npos) << e.what();
  }
  try {
    make_nls_solver("nlopt", {{"algorithm", "LN_BOBYQA"}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("LN_BOBYQA"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gyrosid
