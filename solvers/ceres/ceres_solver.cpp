#include "solvers/ceres/ceres_solver.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>

#include <Eigen/Dense>

#include <cmath>

#include "core/error.h"
#include "core/parallel.h"
#include "solvers/ceres/gaussian_sum_cost.h"
#include "solvers/common/ceres_support.h"
#include "solvers/common/terminations.h"

namespace gyrosid {

OptionTable CeresOptions::table() {
  OptionTable t("ceres");
  t.choice("init", &init, {"ols", "lrols_loo", "ofs_loo", "nlopt"}, "solver whose network starts the optimisation (options: init.<key>=<value>)")
      .integer("max_iterations", &max_iterations, 1, 100000, "Levenberg-Marquardt iterations")
      .choice("linear_solver", &linear_solver, {"dense_qr", "sparse_cholesky"}, "dense QR, or SuiteSparse Cholesky with truncated Gaussians")
      .flag("variable_projection", &variable_projection, "solve the weights linearly inside (Kaufman's variable projection)")
      .real("lambda", &lambda, 0.0, 1e6, "ridge on the weights (unit-RMS target)")
      .flag("covariance", &covariance, "compute parameter standard deviations (ceres::Covariance, dense SVD)")
      .real("truncation", &truncation, 5.0, 700.0, "sparse_cholesky: a Gaussian is zero beyond exp(-truncation)")
      .flag("bias", &bias, "add a constant term to the network")
      .real("function_tolerance", &function_tolerance, 0.0, 1.0, "relative cost change to stop")
      .real("gradient_tolerance", &gradient_tolerance, 0.0, 1.0, "gradient norm to stop")
      .real("parameter_tolerance", &parameter_tolerance, 0.0, 1.0, "relative step to stop")
      .integer("chunk", &chunk, 1, 100000, "samples per residual block")
      .passthrough("init.", &init_options, "an option of the init solver");
  return t;
}

std::string check_init(const std::string& init, const OptionMap& init_options) {
  try {
    make_solver(init, init_options);
  } catch (const Error& e) {
    return str_cat("init solver: ", e.what());
  }
  return "";
}

std::string CeresOptions::validate() const {
  if (covariance && variable_projection) {
    return "covariance=true is not available with variable_projection=true (the weights are not iterated); "
           "drop one of them";
  }
  if (truncation != CeresOptions{}.truncation && linear_solver != "sparse_cholesky") {
    return "truncation applies only to linear_solver=sparse_cholesky";
  }
  return check_init(init, init_options);
}

SolveSummary initial_network(const std::string& init, const OptionMap& init_options, const RbfProblem& problem,
                             RbfNetwork& net) {
  auto solver = make_solver(init, init_options);
  return train(*solver, problem, net);
}

namespace {

ceres::Solver::Options solver_options(const CeresOptions& o) {
  ceres::Solver::Options s;
  s.minimizer_type = ceres::TRUST_REGION;
  s.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  s.linear_solver_type = o.linear_solver == "dense_qr" ? ceres::DENSE_QR : ceres::SPARSE_NORMAL_CHOLESKY;
  s.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  s.max_num_iterations = o.max_iterations;
  s.function_tolerance = o.function_tolerance;
  s.gradient_tolerance = o.gradient_tolerance;
  s.parameter_tolerance = o.parameter_tolerance;
  s.num_threads = worker_threads();
  s.logging_type = ceres::SILENT;
  return s;
}

// Variable projection: residual (N + m) = [y; 0] - [Phi; sqrt(lambda) I] a(theta), a the ridge solution,
// over the node blocks [c, rho] only (the first 2d entries of each NodeBlock). Kaufman's approximation of
// the Jacobian: J_p = -P_perp dPhi/dtheta_p a.
class VarProCost : public ceres::CostFunction {
 public:
  VarProCost(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, int nodes, double lambda)
      : x_(x), y_(y), nodes_(nodes), dim_(static_cast<int>(x.cols())), sqrt_lambda_(std::sqrt(lambda)) {
    set_num_residuals(static_cast<int>(x.rows()) + nodes);
    mutable_parameter_block_sizes()->assign(static_cast<std::size_t>(nodes), 2 * dim_);
  }

  // Basis, its augmented QR and the linear weights at the given nonlinear parameters.
  struct Linear {
    Eigen::MatrixXd phi;
    Eigen::MatrixXd q1;  // thin Q of [Phi; sqrt(lambda) I]
    Eigen::VectorXd a;
  };
  Linear solve(double const* const* p) const {
    const Eigen::Index n = x_.rows(), m = nodes_;
    Eigen::MatrixXd centres(m, dim_), widths(m, dim_);
    for (int j = 0; j < nodes_; ++j) {
      const NodeBlock<const double> node{p[j], dim_};  // its [c, rho]; VarPro leaves the weight out
      for (int k = 0; k < dim_; ++k) centres(j, k) = node.centre()[k], widths(j, k) = std::exp(node.log_width()[k]);
    }
    Linear l;
    l.phi = gaussian_columns(x_, centres, widths);
    Eigen::MatrixXd aug(n + m, m);
    aug.topRows(n) = l.phi;
    aug.bottomRows(m) = sqrt_lambda_ * Eigen::MatrixXd::Identity(m, m);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(aug);
    l.q1 = qr.householderQ() * Eigen::MatrixXd::Identity(n + m, m);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + m);
    rhs.head(n) = y_;
    l.a = qr.solve(rhs);
    return l;
  }

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const Eigen::Index n = x_.rows(), m = nodes_;
    const Linear l = solve(p);
    Eigen::Map<Eigen::VectorXd> r(residuals, n + m);
    r.head(n) = l.phi * l.a - y_;
    r.tail(m) = sqrt_lambda_ * l.a;
    if (!jacobians) return true;
    const int block = 2 * dim_;
    // d(Phi a)/dtheta for node j is a_j times the gradient of phi_j: node_output on the block with weight 1.
    Eigen::MatrixXd dphi_a(n + m, block);
    std::vector<double> node(static_cast<std::size_t>(NodeBlock<double>::size(dim_))), grad(node.size());
    std::vector<double> row(static_cast<std::size_t>(dim_));
    for (int j = 0; j < nodes_; ++j) {
      if (!jacobians[j]) continue;
      std::copy(p[j], p[j] + block, node.begin());
      node.back() = 1.0;
      dphi_a.setZero();
      for (Eigen::Index i = 0; i < n; ++i) {
        for (int k = 0; k < dim_; ++k) row[static_cast<std::size_t>(k)] = x_(i, k);
        node_output(row.data(), {node.data(), dim_}, grad.data());
        for (int c = 0; c < block; ++c) dphi_a(i, c) = grad[static_cast<std::size_t>(c)] * l.a(j);
      }
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(jacobians[j], n + m, block);
      jac = dphi_a - l.q1 * (l.q1.transpose() * dphi_a);  // residual derivative: +P_perp dPhi a
    }
    return true;
  }

 private:
  const Eigen::MatrixXd& x_;
  const Eigen::VectorXd& y_;
  int nodes_, dim_;
  double sqrt_lambda_;
};

// Whether node j is seen above the truncation by any sample of rows [begin, begin + len) (at twice its
// width: a margin for centres and widths to move during the solve).
bool node_near_chunk(const RbfProblem& problem, const RbfNetwork& net, Eigen::Index j, Eigen::Index begin, Eigen::Index len,
                     double truncation) {
  const Eigen::RowVectorXd wide = 2.0 * net.widths.row(j);
  const Eigen::RowVectorXd c = net.centres.row(j);
  for (Eigen::Index i = begin; i < begin + len; ++i) {
    const Eigen::RowVectorXd xi = problem.x.row(i);
    if (-std::log(gaussian(xi.data(), c.data(), wide.data(), xi.size())) < truncation) return true;
  }
  return false;
}

// The packed blocks, one per node (NodeBlock layout), then the optional constant, in one buffer in that order:
// Ceres orders the Jacobian's and the covariance's columns by the blocks' addresses (its orderings are sets of
// pointers), so with a block per allocation the fit's round-off would follow the heap's layout.
struct PackedNetwork {
  Eigen::Index count = 0;  // nodes
  Eigen::Index block = 0;  // parameters per node
  std::vector<double> values;
  explicit PackedNetwork(const RbfNetwork& net)
      : count(net.nodes()), block(NodeBlock<double>::size(net.dimension())), values(static_cast<std::size_t>(count * block + 1)) {
    for (Eigen::Index j = 0; j < count; ++j) net.pack_node(j, node(j));
    bias() = net.bias;
  }
  double* node(Eigen::Index j) { return values.data() + j * block; }
  const double* node(Eigen::Index j) const { return values.data() + j * block; }
  double& bias() { return values.back(); }
  void unpack(RbfNetwork& net, bool with_bias) const {
    for (Eigen::Index j = 0; j < count; ++j) net.unpack_node(j, node(j));
    net.bias = with_bias ? values.back() : 0.0;
  }
};

// Residual blocks of chunks of samples over the nodes each chunk sees (all, unless sparse), plus the ridge.
void add_sample_blocks(const CeresOptions& o, const RbfProblem& problem, const RbfNetwork& net, PackedNetwork& packed,
                       const Baseline* constant, ceres::Problem& cp) {
  const bool sparse = o.linear_solver == "sparse_cholesky";
  for (Eigen::Index begin = 0; begin < problem.size(); begin += o.chunk) {
    const Eigen::Index len = std::min<Eigen::Index>(o.chunk, problem.size() - begin);
    std::vector<double*> blocks;
    for (Eigen::Index j = 0; j < net.nodes(); ++j) {
      if (sparse && !node_near_chunk(problem, net, j, begin, len, o.truncation)) continue;
      blocks.push_back(packed.node(j));
    }
    if (constant) blocks.push_back(&packed.bias());
    const int nodes_here = static_cast<int>(blocks.size()) - (constant ? 1 : 0);
    cp.AddResidualBlock(new GaussianSumCost(problem.x.middleRows(begin, len), problem.y.segment(begin, len), nodes_here, constant),
                        nullptr, blocks);
  }
  if (o.lambda > 0) {
    for (Eigen::Index j = 0; j < packed.count; ++j) {
      cp.AddResidualBlock(new WeightPrior(static_cast<int>(net.dimension()), std::sqrt(o.lambda)), nullptr, packed.node(j));
    }
  }
}

// Standard deviations of every node's parameters from ceres::Covariance, scaled by the residual variance.
nlohmann::json parameter_sigmas(PackedNetwork& packed, ceres::Problem& cp, double final_cost, Eigen::Index n) {
  ceres::Covariance covariance(dense_svd_covariance());
  std::vector<std::pair<const double*, const double*>> pairs;
  for (Eigen::Index j = 0; j < packed.count; ++j) pairs.emplace_back(packed.node(j), packed.node(j));
  if (!covariance.Compute(pairs, &cp)) return {{"parameter_sigma", "rank-deficient Jacobian: covariance not computable"}};
  const auto block = static_cast<int>(packed.block);
  const double params = static_cast<double>(packed.count) * block;
  const double sigma2 = 2.0 * final_cost / std::max(1.0, static_cast<double>(n) - params);  // residual variance
  nlohmann::json sig = nlohmann::json::array();
  std::vector<double> cov(static_cast<std::size_t>(block * block));
  for (Eigen::Index j = 0; j < packed.count; ++j) {
    covariance.GetCovarianceBlock(packed.node(j), packed.node(j), cov.data());
    std::vector<double> sd(static_cast<std::size_t>(block));
    for (int k = 0; k < block; ++k) sd[static_cast<std::size_t>(k)] = std::sqrt(std::max(0.0, sigma2 * cov[static_cast<std::size_t>(k * block + k)]));
    sig.push_back(sd);
  }
  return {{"parameter_sigma", sig}, {"residual_sigma", std::sqrt(sigma2)}};
}

}  // namespace

SolveOutcome CeresRbfSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const CeresOptions& o = o_;
  const SolveSummary init = initial_network(o.init, o.init_options, problem, net);
  PackedNetwork packed(net);
  const Baseline constant{1, [](const double*, const double* beta, double* g) {
                            if (g) g[0] = 1.0;
                            return beta[0];
                          }};
  MonitorCallback callback(monitor);
  ceres::Solver::Options solve_options = solver_options(o);
  solve_options.callbacks.push_back(&callback);
  ceres::Problem cp;
  ceres::Solver::Summary summary;
  if (o.variable_projection) {
    std::vector<double*> blocks;
    for (Eigen::Index j = 0; j < packed.count; ++j) blocks.push_back(packed.node(j));
    auto* cost = new VarProCost(problem.x, problem.y, static_cast<int>(net.nodes()), o.lambda);
    cp.AddResidualBlock(cost, nullptr, blocks);
    ceres::Solve(solve_options, &cp, &summary);
    const VarProCost::Linear l = cost->solve(blocks.data());
    for (Eigen::Index j = 0; j < net.nodes(); ++j) NodeBlock<double>{packed.node(j), problem.dimension()}.weight() = l.a(j);
  } else {
    add_sample_blocks(o, problem, net, packed, o.bias ? &constant : nullptr, cp);
    ceres::Solve(solve_options, &cp, &summary);
  }
  packed.unpack(net, o.bias);
  monitor.evaluation(summary.num_residual_evaluations);

  SolveOutcome out{termination_of(summary.termination_type), summary.message,
                   {{"init", init},
                    {"initial_cost", summary.initial_cost},
                    {"final_cost", summary.final_cost},
                    {"linear_solver", o.linear_solver},
                    {"variable_projection", o.variable_projection},
                    {"residual_blocks", summary.num_residual_blocks},
                    {"jacobian_seconds", summary.jacobian_evaluation_time_in_seconds},
                    {"linear_solver_seconds", summary.linear_solver_time_in_seconds}}};
  if (o.covariance) out.details.update(parameter_sigmas(packed, cp, summary.final_cost, problem.size()));
  return out;
}

}  // namespace gyrosid
