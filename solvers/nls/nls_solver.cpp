#include "solvers/nls/nls_solver.h"

#include <ceres/ceres.h>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>
#include <nlopt.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "solvers/common/ceres_support.h"
#include "solvers/common/ipopt_support.h"
#include "solvers/common/terminations.h"
#include "solvers/nls/nls_scaling.h"

namespace gyrosid {

// --- options ---------------------------------------------------------------------------------------

OptionTable NlsCeresOptions::table() {
  OptionTable t("nls ceres");
  t.integer("max_iterations", &max_iterations, 1, 100000, "Levenberg-Marquardt iterations")
      .choice("linear_solver", &linear_solver, {"dense_qr", "dense_normal_cholesky", "sparse_normal_cholesky"},
              "linear solver of each step (dense QR is the stable default)")
      .real("function_tolerance", &function_tolerance, 0.0, 1.0, "relative cost change to stop")
      .real("gradient_tolerance", &gradient_tolerance, 0.0, 1.0, "scaled gradient norm to stop")
      .real("parameter_tolerance", &parameter_tolerance, 0.0, 1.0, "relative step to stop");
  return t;
}
std::string NlsCeresOptions::validate() const { return ""; }

OptionTable NlsNloptOptions::table() {
  OptionTable t("nls nlopt");
  t.text("algorithm", &algorithm, "gradient-based NLopt algorithm: LD_LBFGS, LD_TNEWTON_PRECOND_RESTART, LD_SLSQP, LD_MMA, LD_VAR2, ...")
      .integer("max_evaluations", &max_evaluations, 2, 10000000, "objective-and-gradient evaluations allowed")
      .real("ftol_rel", &ftol_rel, 0.0, 1.0, "relative change of F to stop")
      .real("xtol_rel", &xtol_rel, 0.0, 1.0, "relative change of the scaled parameters to stop");
  return t;
}
std::string NlsNloptOptions::validate() const {
  const nlopt_algorithm a = nlopt_algorithm_from_string(algorithm.c_str());
  if (static_cast<int>(a) < 0 || a >= NLOPT_NUM_ALGORITHMS) {
    return str_cat("option 'algorithm' = '", algorithm, "' is not an NLopt algorithm (e.g. LD_LBFGS, LD_SLSQP)");
  }
  if (algorithm.rfind("LD_", 0) != 0) {
    return str_cat("option 'algorithm' = '", algorithm, "': a least-squares problem has gradients - use a local gradient-based (LD_*) algorithm");
  }
  return "";
}

OptionTable NlsIpoptOptions::table() {
  OptionTable t("nls ipopt");
  t.choice("hessian", &hessian, {"gauss_newton", "limited_memory"}, "Hessian of the objective: J'J or L-BFGS")
      .integer("max_iterations", &max_iterations, 1, 100000, "Ipopt iterations")
      .real("tolerance", &tolerance, 0.0, 1.0, "Ipopt convergence tolerance (on the scaled problem)", true)
      .integer("print_level", &print_level, 0, 12, "Ipopt's own console output (0: silent)");
  return t;
}
std::string NlsIpoptOptions::validate() const { return ""; }

namespace {

// --- ceres -----------------------------------------------------------------------------------------

ceres::LinearSolverType linear_solver_type(const std::string& name) {
  if (name == "dense_normal_cholesky") return ceres::DENSE_NORMAL_CHOLESKY;
  if (name == "sparse_normal_cholesky") return ceres::SPARSE_NORMAL_CHOLESKY;
  return ceres::DENSE_QR;
}

class CeresNls : public NlsSolverWithOptions<NlsCeresOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "ceres"; }

  SolveOutcome minimize(NlsProblem& p, SolveMonitor& monitor) override {
    ceres::Problem problem = ceres_problem(p);
    ceres::Solver::Options s;
    s.minimizer_type = ceres::TRUST_REGION;
    s.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    s.linear_solver_type = linear_solver_type(o_.linear_solver);
    s.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    s.max_num_iterations = o_.max_iterations;
    s.function_tolerance = o_.function_tolerance;
    s.gradient_tolerance = o_.gradient_tolerance;
    s.parameter_tolerance = o_.parameter_tolerance;
    s.num_threads = 1;  // deterministic; the machine is shared
    s.logging_type = ceres::SILENT;
    MonitorCallback callback(monitor);
    s.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(s, &problem, &summary);
    monitor.evaluation(summary.num_residual_evaluations);
    return {termination_of(summary.termination_type), summary.message,
            {{"successful_steps", summary.num_successful_steps}, {"unsuccessful_steps", summary.num_unsuccessful_steps},
             {"linear_solver", o_.linear_solver}}};
  }
};

// --- nlopt -----------------------------------------------------------------------------------------

class NloptNls : public NlsSolverWithOptions<NlsNloptOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "nlopt"; }

  SolveOutcome minimize(NlsProblem& p, SolveMonitor& monitor) override {
    ScaledObjective f(p, monitor);
    const auto n = static_cast<unsigned>(f.size());
    if (n == 0) return {Termination::converged, "no free parameters", {}};
    nlopt_opt opt = nlopt_create(nlopt_algorithm_from_string(o_.algorithm.c_str()), n);
    if (!opt) fail("nls nlopt: cannot create algorithm ", o_.algorithm);
    std::vector<double> u(f.start().data(), f.start().data() + n);
    if (p.bounded()) {
      const Eigen::VectorXd lo = f.scaled_lower(), hi = f.scaled_upper();
      nlopt_set_lower_bounds(opt, lo.data());
      nlopt_set_upper_bounds(opt, hi.data());
    }
    nlopt_set_min_objective(opt, &NloptNls::objective, &f);
    nlopt_set_maxeval(opt, o_.max_evaluations);
    nlopt_set_ftol_rel(opt, o_.ftol_rel);
    nlopt_set_xtol_rel(opt, o_.xtol_rel);
    double value = 0.0;
    const nlopt_result result = nlopt_optimize(opt, u.data(), &value);
    nlopt_destroy(opt);
    // Keep the best point evaluated (NLopt's round-off stop may return a worse one).
    f.store_best();
    return {termination_of(result), nlopt_result_to_string(result), {{"algorithm", o_.algorithm}}};
  }

 private:
  static double objective(unsigned n, const double* u, double* grad, void* data) {
    auto* f = static_cast<ScaledObjective*>(data);
    Eigen::VectorXd g;
    const double v = f->value(Eigen::Map<const Eigen::VectorXd>(u, n), grad ? &g : nullptr, nullptr);
    if (grad) Eigen::Map<Eigen::VectorXd>(grad, n) = g;
    return v;
  }
};

// --- ipopt -----------------------------------------------------------------------------------------

using Ipopt::Index;
using Ipopt::Number;

class NlsNlp : public Ipopt::TNLP {
 public:
  NlsNlp(ScaledObjective& f, bool exact_hessian) : f_(f), exact_(exact_hessian) {}
  Ipopt::SolverReturn status = Ipopt::UNASSIGNED;

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override {
    n = static_cast<Index>(f_.size());
    m = 0;
    nnz_jac = 0;
    nnz_h = exact_ ? n * (n + 1) / 2 : 0;
    style = TNLP::C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index, Number*, Number*) override {
    const Eigen::VectorXd lo = f_.scaled_lower(), hi = f_.scaled_upper();
    for (Index i = 0; i < n; ++i) {
      xl[i] = std::isfinite(lo(i)) ? lo(i) : -2e19;
      xu[i] = std::isfinite(hi(i)) ? hi(i) : 2e19;
    }
    return true;
  }
  bool get_starting_point(Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    Eigen::Map<Eigen::VectorXd>(x, n) = f_.start();
    return true;
  }
  bool eval_f(Index n, const Number* x, bool, Number& obj) override {
    obj = f_.value(Eigen::Map<const Eigen::VectorXd>(x, n), nullptr, nullptr);
    return std::isfinite(obj);
  }
  bool eval_grad_f(Index n, const Number* x, bool, Number* grad) override {
    Eigen::VectorXd g;
    f_.value(Eigen::Map<const Eigen::VectorXd>(x, n), &g, nullptr);
    Eigen::Map<Eigen::VectorXd>(grad, n) = g;
    return true;
  }
  bool eval_g(Index, const Number*, bool, Index, Number*) override { return true; }
  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index*, Index*, Number*) override { return true; }
  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index, const Number*, bool, Index, Index* row,
              Index* col, Number* values) override {
    Index at = 0;
    if (!values) {
      for (Index i = 0; i < n; ++i)
        for (Index j = 0; j <= i; ++j) row[at] = i, col[at++] = j;
      return true;
    }
    Eigen::MatrixXd h;
    f_.value(Eigen::Map<const Eigen::VectorXd>(x, n), nullptr, &h);
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j <= i; ++j) values[at++] = obj_factor * h(i, j);
    return true;
  }
  bool intermediate_callback(Ipopt::AlgorithmMode, Index, Number obj, Number, Number, Number, Number, Number, Number,
                             Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    f_.report(obj);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn s, Index, const Number*, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status = s;
  }

 private:
  ScaledObjective& f_;
  bool exact_;
};

class IpoptNls : public NlsSolverWithOptions<NlsIpoptOptions> {
 public:
  using WithOptions::WithOptions;
  std::string_view name() const override { return "ipopt"; }

  SolveOutcome minimize(NlsProblem& p, SolveMonitor& monitor) override {
    ScaledObjective f(p, monitor, /*report_every_evaluation=*/false);
    if (f.size() == 0) return {Termination::converged, "no free parameters", {}};
    Ipopt::SmartPtr<NlsNlp> nlp = new NlsNlp(f, o_.hessian == "gauss_newton");
    const Ipopt::ApplicationReturnStatus status =
        solve_with_ipopt(nlp, {o_.print_level, o_.hessian == "gauss_newton", o_.max_iterations, o_.tolerance}, "nls ipopt");
    f.store_best();
    return {termination_of(nlp->status), str_cat("Ipopt application status ", static_cast<int>(status)), {{"hessian", o_.hessian}}};
  }
};

template <typename S>
NlsSolverRegistry::Entry nls_entry(std::string name, std::string summary) {
  return options_entry<NlsSolver, S>(std::move(name), std::move(summary), "nls solver ");
}

}  // namespace

const NlsSolverRegistry& nls_solvers() {
  static const NlsSolverRegistry registry = [] {
    NlsSolverRegistry r("nonlinear least-squares solver");
    r.add(nls_entry<CeresNls>("ceres", "Levenberg-Marquardt on the residual blocks (Ceres Solver)"))
        .add(nls_entry<NloptNls>("nlopt", "a gradient-based NLopt algorithm on 1/2 |r|^2 (default L-BFGS)"))
        .add(nls_entry<IpoptNls>("ipopt", "interior point with the Gauss-Newton Hessian (Ipopt)"));
    return r;
  }();
  return registry;
}

std::unique_ptr<NlsSolver> make_nls_solver(const std::string& name, const OptionMap& options) {
  return nls_solvers().make(name, options);
}

SolveSummary solve(NlsSolver& solver, NlsProblem& problem) {
  SolveSummary s = timed_solve(std::string(solver.name()), [&](SolveMonitor& monitor) { return solver.minimize(problem, monitor); });
  s.details["residuals"] = problem.residual_count();
  s.details["free_parameters"] = problem.free_entries().size();
  s.details["cost"] = problem.evaluate(problem.free_values());
  return s;
}

}  // namespace gyrosid
