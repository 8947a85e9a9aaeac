#include "solvers/ceres/ceres_solver.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>

#include <Eigen/Dense>

#include <chrono>
#include <cmath>

#include "core/error.h"
#include "core/parallel.h"
#include "solvers/ceres/gaussian_sum_cost.h"

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
      .integer("chunk", &chunk, 1, 100000, "samples per residual block");
  return t;
}

CeresRbfSolver::CeresRbfSolver(const OptionMap& options) { init_options_ = options_.table().apply(options, "init."); }

std::string CeresRbfSolver::help() {
  CeresOptions o;
  return "ceres - joint Levenberg-Marquardt over centres, log-widths and weights (Ceres Solver):\n" + o.table().help();
}

SolverSummary initial_network(const std::string& init, const OptionMap& init_options, const RbfProblem& problem,
                              RbfNetwork& net) {
  auto solver = make_solver(init, init_options);
  return solver->train(problem, net);
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
// over the node blocks [c, rho] only. Kaufman's approximation of the Jacobian: J_p = -P_perp dPhi/dtheta_p a.
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
    Linear l;
    l.phi.resize(n, m);
    for (int j = 0; j < nodes_; ++j)
      for (Eigen::Index i = 0; i < n; ++i) {
        double z = 0.0;
        for (int k = 0; k < dim_; ++k) {
          const double u = (x_(i, k) - p[j][k]) / std::exp(p[j][dim_ + k]);
          z += u * u;
        }
        l.phi(i, j) = std::exp(-z);
      }
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
    Eigen::VectorXd v(n + m);
    for (int j = 0; j < nodes_; ++j) {
      if (!jacobians[j]) continue;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(jacobians[j], n + m, block);
      for (int c = 0; c < block; ++c) {
        v.setZero();
        const int k = c % dim_;
        const double rk = std::exp(p[j][dim_ + k]);
        for (Eigen::Index i = 0; i < n; ++i) {
          const double u = (x_(i, k) - p[j][k]) / rk;
          const double dphi = c < dim_ ? l.phi(i, j) * 2.0 * u / rk : l.phi(i, j) * 2.0 * u * u;
          v(i) = dphi * l.a(j);
        }
        jac.col(c) = v - l.q1 * (l.q1.transpose() * v);  // residual derivative: +P_perp dPhi a
      }
    }
    return true;
  }

 private:
  const Eigen::MatrixXd& x_;
  const Eigen::VectorXd& y_;
  int nodes_, dim_;
  double sqrt_lambda_;
};

}  // namespace

SolverSummary CeresRbfSolver::train(const RbfProblem& problem, RbfNetwork& net) {
  const auto start = std::chrono::steady_clock::now();
  const CeresOptions& o = options_;
  const SolverSummary init = initial_network(o.init, init_options_, problem, net);
  const Eigen::Index n = problem.size(), m = net.nodes(), d = problem.dimension();
  const int block = static_cast<int>(2 * d + 1);

  // Parameter blocks [c, log r, w] per node (+ bias).
  std::vector<std::vector<double>> params(static_cast<std::size_t>(m), std::vector<double>(static_cast<std::size_t>(block)));
  for (Eigen::Index j = 0; j < m; ++j) {
    auto& b = params[static_cast<std::size_t>(j)];
    for (Eigen::Index k = 0; k < d; ++k) {
      b[static_cast<std::size_t>(k)] = net.centres(j, k);
      b[static_cast<std::size_t>(d + k)] = std::log(net.widths(j, k));
    }
    b[static_cast<std::size_t>(2 * d)] = net.weights(j);
  }
  double bias = net.bias;
  Baseline constant{1, [](const double*, const double* beta, double* g) {
                      if (g) g[0] = 1.0;
                      return beta[0];
                    }};

  ceres::Problem::Options problem_options;
  ceres::Problem ceres_problem(problem_options);
  ceres::Solver::Summary summary;
  const ceres::Solver::Options solve_options = solver_options(o);
  if (o.variable_projection) {
    // Only [c, log r] are iterated; the block layout keeps w last, so pass the first 2d entries.
    std::vector<double*> blocks;
    for (auto& b : params) blocks.push_back(b.data());
    auto* cost = new VarProCost(problem.x, problem.y, static_cast<int>(m), o.lambda);
    ceres_problem.AddResidualBlock(cost, nullptr, blocks);
    ceres::Solve(solve_options, &ceres_problem, &summary);
    const VarProCost::Linear l = cost->solve(blocks.data());
    for (Eigen::Index j = 0; j < m; ++j) params[static_cast<std::size_t>(j)][static_cast<std::size_t>(2 * d)] = l.a(j);
  } else {
    const bool sparse = o.linear_solver == "sparse_cholesky";
    for (Eigen::Index begin = 0; begin < n; begin += o.chunk) {
      const Eigen::Index len = std::min<Eigen::Index>(o.chunk, n - begin);
      std::vector<double*> blocks;
      for (Eigen::Index j = 0; j < m; ++j) {
        if (sparse) {
          // Keep node j if any sample of the chunk sees it above the truncation (at 2x the width, a margin
          // for the centres and widths to move during the solve).
          bool near = false;
          for (Eigen::Index i = begin; i < begin + len && !near; ++i) {
            double z = 0.0;
            for (Eigen::Index k = 0; k < d; ++k) {
              const double u = (problem.x(i, k) - net.centres(j, k)) / (2.0 * net.widths(j, k));
              z += u * u;
            }
            near = z < o.truncation;
          }
          if (!near) continue;
        }
        blocks.push_back(params[static_cast<std::size_t>(j)].data());
      }
      if (o.bias) blocks.push_back(&bias);
      const int nodes_here = static_cast<int>(blocks.size()) - (o.bias ? 1 : 0);
      ceres_problem.AddResidualBlock(
          new GaussianSumCost(problem.x.middleRows(begin, len), problem.y.segment(begin, len), nodes_here, o.bias ? &constant : nullptr),
          nullptr, blocks);
    }
    if (o.lambda > 0) {
      for (auto& b : params) ceres_problem.AddResidualBlock(new WeightPrior(block, std::sqrt(o.lambda)), nullptr, b.data());
    }
    ceres::Solve(solve_options, &ceres_problem, &summary);
  }

  for (Eigen::Index j = 0; j < m; ++j) {
    const auto& b = params[static_cast<std::size_t>(j)];
    for (Eigen::Index k = 0; k < d; ++k) {
      net.centres(j, k) = b[static_cast<std::size_t>(k)];
      net.widths(j, k) = std::exp(b[static_cast<std::size_t>(d + k)]);
    }
    net.weights(j) = b[static_cast<std::size_t>(2 * d)];
  }
  net.bias = o.bias ? bias : 0.0;

  SolverSummary s;
  s.solver = "ceres";
  s.termination = ceres::TerminationTypeToString(summary.termination_type);
  s.iterations = static_cast<int>(summary.iterations.size());
  for (const auto& it : summary.iterations) s.cost_history.push_back(it.cost);
  s.nodes = static_cast<int>(m);
  s.details = {{"init", init.to_json()},
               {"initial_cost", summary.initial_cost},
               {"final_cost", summary.final_cost},
               {"linear_solver", o.linear_solver},
               {"variable_projection", o.variable_projection},
               {"message", summary.message},
               {"residual_blocks", summary.num_residual_blocks},
               {"jacobian_seconds", summary.jacobian_evaluation_time_in_seconds},
               {"linear_solver_seconds", summary.linear_solver_time_in_seconds}};

  if (o.covariance && !o.variable_projection) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs;
    for (auto& b : params) pairs.emplace_back(b.data(), b.data());
    if (covariance.Compute(pairs, &ceres_problem)) {
      const double dof = std::max<double>(1.0, static_cast<double>(n) - static_cast<double>(m * block));
      const double sigma2 = 2.0 * summary.final_cost / dof;  // residual variance (scaled target units)
      nlohmann::json sig = nlohmann::json::array();
      std::vector<double> cov(static_cast<std::size_t>(block * block));
      for (auto& b : params) {
        covariance.GetCovarianceBlock(b.data(), b.data(), cov.data());
        std::vector<double> sd(static_cast<std::size_t>(block));
        for (int k = 0; k < block; ++k) sd[static_cast<std::size_t>(k)] = std::sqrt(std::max(0.0, sigma2 * cov[static_cast<std::size_t>(k * block + k)]));
        sig.push_back(sd);
      }
      s.details["parameter_sigma"] = sig;  // per node: centre, log width, weight (weights in target units)
      s.details["residual_sigma"] = std::sqrt(sigma2);
    } else {
      s.details["parameter_sigma"] = "rank-deficient Jacobian: covariance not computable";
    }
  }
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.peak_rss_mb = peak_rss_mb();
  return s;
}

}  // namespace gyrosid
