// The RBF solvers: a planted network recovered from noise-free data, the recursive leave-one-out of the
// forward selection against brute-force refits, option validation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "core/error.h"
#include "solvers/ols/forward_selection.h"
#include "solvers/solver.h"
#include "error_of.h"
#include "planted_problem.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using testing_support::Planted;
using testing_support::planted_problem;

RbfNetwork train(const std::string& solver, const OptionMap& options) {
  const RbfProblem p = planted_problem();
  RbfNetwork net = p.empty_network();
  const SolveSummary s = gyrosid::train(*make_solver(solver, options), p, net);
  EXPECT_TRUE(s.usable()) << solver << ": " << s.message;
  EXPECT_EQ(s.iterations, static_cast<int>(s.cost_history.size()));
  return net;
}

// Largest |network - planted| on an off-grid test set.
double worst_error(const RbfNetwork& net) {
  const Planted f;
  double worst = 0;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const double x[2] = {-0.99 + 1.98 * i / 39, -0.98 + 1.96 * j / 39};
      worst = std::max(worst, std::abs(net.predict(x) - f(x[0], x[1])));
    }
  return worst;
}

// Every planted node is in the network with its weight and width; any other node has weight ~0.
void expect_planted_nodes(const RbfNetwork& net, double tolerance) {
  const Planted f;
  std::vector<bool> matched(static_cast<std::size_t>(net.nodes()), false);
  for (int j = 0; j < 5; ++j) {
    bool found = false;
    for (Eigen::Index n = 0; n < net.nodes(); ++n) {
      if (std::abs(net.centres(n, 0) - f.c[j][0]) < tolerance && std::abs(net.centres(n, 1) - f.c[j][1]) < tolerance) {
        EXPECT_NEAR(net.weights(n), f.w[j], tolerance) << "node at " << f.c[j][0] << ", " << f.c[j][1];
        EXPECT_NEAR(net.widths(n, 0), f.r, tolerance);
        EXPECT_NEAR(net.widths(n, 1), f.r, tolerance);
        matched[static_cast<std::size_t>(n)] = found = true;
      }
    }
    EXPECT_TRUE(found) << "planted node " << j << " not recovered";
  }
  for (Eigen::Index n = 0; n < net.nodes(); ++n) {
    if (!matched[static_cast<std::size_t>(n)]) {
      EXPECT_NEAR(net.weights(n), 0.0, tolerance);
    }
  }
}

TEST(Solvers, OlsRecoversAPlantedNetwork) {
  const RbfNetwork net = train("ols", {{"width", "0.3"}, {"lambda", "1e-12"}, {"reestimate_lambda", "false"}, {"candidates", "0"}});
  EXPECT_LT(worst_error(net), 1e-9);
  expect_planted_nodes(net, 1e-7);
}

TEST(Solvers, LrolsLooRecoversAPlantedNetwork) {
  const RbfNetwork net = train("lrols_loo", {{"width", "0.3"}, {"lambda", "1e-12"}, {"candidates", "0"}});
  EXPECT_LT(worst_error(net), 1e-9);
  expect_planted_nodes(net, 1e-7);
}

TEST(Solvers, CeresAndIpoptRecoverAPlantedNetworkFromAWrongWidth) {
  // The OLS start uses width 0.25 with the five-node budget; the joint optimisation must move every
  // centre, width and weight to the planted values.
  for (const char* solver : {"ceres", "ipopt"}) {
    OptionMap o{{"init.width", "0.25"}, {"init.candidates", "0"}};
    o[std::string(solver) == "ceres" ? "init.max_nodes" : "nodes"] = "5";
    const RbfNetwork net = train(solver, o);
    EXPECT_EQ(net.nodes(), 5) << solver;
    EXPECT_LT(worst_error(net), 1e-7) << solver;
    expect_planted_nodes(net, 1e-6);
  }
}

TEST(Solvers, CeresVariableProjectionAndSparseCholeskyAgree) {
  for (const OptionMap& extra : {OptionMap{{"variable_projection", "true"}}, OptionMap{{"linear_solver", "sparse_cholesky"}}}) {
    OptionMap o{{"init.width", "0.25"}, {"init.candidates", "0"}, {"init.max_nodes", "5"}};
    o.insert(extra.begin(), extra.end());
    const RbfNetwork net = train("ceres", o);
    EXPECT_LT(worst_error(net), 1e-6) << extra.begin()->first;
    expect_planted_nodes(net, 1e-5);
  }
}

TEST(Solvers, NloptFindsThePlantedWidth) {
  // The hyper-parameter search lands near the planted width; the inner OLS then fits the function.
  const RbfNetwork net = train("nlopt", {{"candidates", "0"}, {"per_input_widths", "false"}, {"evaluations", "60"}});
  EXPECT_NEAR(net.widths(0, 0), 0.3, 0.015);
  EXPECT_LT(worst_error(net), 1e-5);
}

TEST(Solvers, OfsLooBuildsAParsimoniousAccurateNetwork) {
  // Greedy tuning of one node at a time does not land on the planted nodes exactly (the first node must
  // stand in for the others), but it is accurate with few nodes and its first nodes sit by planted ones.
  const RbfNetwork net = train("ofs_loo", {});
  EXPECT_LT(worst_error(net), 2e-3);
  EXPECT_LT(net.nodes(), 150);
  const Planted f;
  int near = 0;
  for (int j = 0; j < 5; ++j) {
    for (Eigen::Index n = 0; n < std::min<Eigen::Index>(5, net.nodes()); ++n) {
      if (std::hypot(net.centres(n, 0) - f.c[j][0], net.centres(n, 1) - f.c[j][1]) < 0.1) {
        ++near;
        break;
      }
    }
  }
  EXPECT_GE(near, 4);
}

// Brute-force leave-one-out of a ridge fit on orthogonal columns W with penalty lambda on their weights.
double brute_force_loo(const Eigen::MatrixXd& w, const Eigen::VectorXd& y, double lambda) {
  const Eigen::Index n = w.rows(), k = w.cols();
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::MatrixXd wi(n - 1, k);
    Eigen::VectorXd yi(n - 1);
    wi << w.topRows(i), w.bottomRows(n - 1 - i);
    yi << y.head(i), y.tail(n - 1 - i);
    const Eigen::MatrixXd a = wi.transpose() * wi + lambda * Eigen::MatrixXd::Identity(k, k);
    const Eigen::VectorXd g = a.ldlt().solve(wi.transpose() * yi);
    const double e = y(i) - w.row(i).dot(g);
    sum += e * e;
  }
  return sum / static_cast<double>(n);
}

TEST(Solvers, RecursiveLeaveOneOutEqualsBruteForceRefits) {
  // A small noisy problem; the forward selection's LOO after every step against n refits with sample i
  // left out, on the same orthogonalised columns (the identity e_i / (1 - h_ii) is exact for them).
  RbfProblem p = planted_problem();
  for (Eigen::Index i = 0; i < p.y.size(); ++i) p.y(i) += 0.05 * std::sin(37.0 * i);
  ForwardSelectionOptions o;
  o.criterion = SelectionCriterion::loo;
  o.widths = Eigen::RowVectorXd::Constant(2, 0.35);
  o.candidates = 60;
  o.max_nodes = 12;
  o.lambda = 1e-3;
  o.reestimate_lambda = false;
  o.patience = 1000;
  const ForwardSelectionResult r = forward_select(p.x, p.y, o);
  ASSERT_EQ(r.criterion_history.size(), 12u);
  // The kept network is cut back to the best step; its centres are the first selected ones, in order.
  // Rebuild those columns and orthogonalise them (Householder QR: W = Q diag(R), the same projector).
  const Eigen::Index kept = r.centres.rows();
  ASSERT_GE(kept, 4);
  Eigen::MatrixXd phi(p.x.rows(), kept);
  for (Eigen::Index j = 0; j < kept; ++j)
    for (Eigen::Index i = 0; i < p.x.rows(); ++i) {
      const double u = (p.x(i, 0) - r.centres(j, 0)) / 0.35, v = (p.x(i, 1) - r.centres(j, 1)) / 0.35;
      phi(i, j) = std::exp(-u * u - v * v);
    }
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(phi);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(phi.rows(), kept);
  const Eigen::VectorXd d = qr.matrixQR().diagonal().head(kept);
  for (int k = 1; k <= kept; ++k) {
    const Eigen::MatrixXd w = q.leftCols(k) * d.head(k).asDiagonal();
    EXPECT_NEAR(r.criterion_history[static_cast<std::size_t>(k - 1)], brute_force_loo(w, p.y, 1e-3),
                1e-10 * r.criterion_history[static_cast<std::size_t>(k - 1)])
        << k << " nodes";
  }
}

using testing_support::error_of;

TEST(Solvers, InvalidOptionsAreRejectedWithTheOptionAndItsRange) {
  EXPECT_THAT(error_of([] { make_solver("ols", {{"widht", "0.3"}}); }), HasSubstr("unknown option 'widht'; known: criterion, width"));
  EXPECT_THAT(error_of([] { make_solver("ols", {{"width", "-1"}}); }), HasSubstr("'width' = -1 is outside its range (0, 1e+06]"));
  EXPECT_THAT(error_of([] { make_solver("ols", {{"criterion", "aic"}}); }), HasSubstr("allowed: bic|gcv|uev|fpe|loo"));
  EXPECT_THAT(error_of([] { make_solver("lrols_loo", {{"passes", "two"}}); }), HasSubstr("'passes' = 'two' is not an integer"));
  EXPECT_THAT(error_of([] { make_solver("nlopt", {{"algorithm", "LD_LBFGS"}}); }), HasSubstr("needs gradients"));
  EXPECT_THAT(error_of([] { make_solver("nlopt", {{"algorithm", "LN_NOPE"}}); }), HasSubstr("is not an NLopt algorithm"));
  EXPECT_THAT(error_of([] { make_solver("ceres", {{"linear_solver", "cholesky"}}); }), HasSubstr("allowed: dense_qr|sparse_cholesky"));
  EXPECT_THAT(error_of([] { make_solver("ipopt", {{"min_width", "2"}, {"max_width", "1"}}); }), HasSubstr("min_width must be below max_width"));
  EXPECT_THAT(error_of([] { make_solver("ofs_loo", {{"width", "5"}}); }), HasSubstr("outside [min_width, max_width]"));
  EXPECT_THAT(error_of([] { make_solver("simplex", {}); }), HasSubstr("unknown solver 'simplex'; known: ols, lrols_loo, ofs_loo, ceres, nlopt, ipopt"));
}

}  // namespace
}  // namespace gyrosid
