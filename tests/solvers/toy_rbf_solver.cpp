// A toy RBF solver added from the test binary alone, proving the extension point of solvers/solver.h: a
// solver is an options struct, a class and one registration line; the property suite of
// test_solver_properties.cpp then runs over it like over the library's own.
//
// grid_ls: Gaussian nodes of one width on a regular grid over [-1, 1]^d (normalised inputs), weights and the
// constant by least squares (column-pivoted QR on the N x (m + 1) basis, no normal equations).
#include <Eigen/QR>

#include <cmath>

#include "solvers/solver.h"

namespace gyrosid {
namespace {

struct GridLsOptions {
  int nodes_per_axis = 11;
  double width = 0.3;
  OptionTable table() {
    OptionTable t("grid_ls");
    t.integer("nodes_per_axis", &nodes_per_axis, 2, 50, "grid nodes along each normalised input")
        .real("width", &width, 0.0, 10.0, "every node's width, normalised units", true);
    return t;
  }
  std::string validate() const { return ""; }
};

class GridLsSolver : public RbfSolverWithOptions<GridLsOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "grid_ls"; }
  SolveOutcome fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) override {
    const Eigen::Index d = problem.dimension(), k = o_.nodes_per_axis;
    const auto m = static_cast<Eigen::Index>(std::pow(static_cast<double>(k), static_cast<double>(d)));
    net.centres.resize(m, d);
    for (Eigen::Index j = 0; j < m; ++j) {
      for (Eigen::Index a = 0, rest = j; a < d; ++a, rest /= k) net.centres(j, a) = -1.0 + 2.0 * static_cast<double>(rest % k) / static_cast<double>(k - 1);
    }
    net.widths = Eigen::MatrixXd::Constant(m, d, o_.width);
    net.weights = Eigen::VectorXd::Zero(m);
    Eigen::MatrixXd a(problem.size(), m + 1);
    a.leftCols(m) = net.basis(problem.x);
    a.col(m).setOnes();
    const Eigen::VectorXd c = a.colPivHouseholderQr().solve(problem.y);
    net.weights = c.head(m);
    net.bias = c(m);
    monitor.evaluation();
    monitor.iteration((a * c - problem.y).squaredNorm());
    return {Termination::converged, "least squares on a fixed grid of nodes", {}};
  }
};

// The one registration line, run before gtest lists or instantiates the tests.
const bool registered = [] {
  extend_rbf_solvers().add(solver_entry<GridLsSolver>("grid_ls", "toy: fixed grid of nodes, weights by least squares"));
  return true;
}();

}  // namespace
}  // namespace gyrosid
