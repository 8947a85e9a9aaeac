#include "solvers/ipopt/ipopt_solver.h"

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "solvers/ceres/ceres_solver.h"

namespace gyrosid {

OptionTable IpoptOptions::table() {
  OptionTable t("ipopt");
  t.choice("init", &init, {"ols", "lrols_loo", "ofs_loo", "nlopt"}, "solver whose network (cut at the budget) starts the optimisation")
      .integer("nodes", &nodes, 1, 100000, "node budget")
      .real("min_width", &min_width, 0.0, 1e6, "lower bound of the widths", true)
      .real("max_width", &max_width, 0.0, 1e6, "upper bound of the widths", true)
      .choice("constraint", &constraint, {"none", "weight_norm", "roughness"}, "inequality constraint")
      .real("bound", &bound, 0.0, 1e30, "upper bound of the constraint (0: 1.5 x its starting value)")
      .real("lambda", &lambda, 0.0, 1e6, "ridge on the weights")
      .choice("hessian", &hessian, {"gauss_newton", "limited_memory"}, "Hessian of the Lagrangian: J'J or L-BFGS")
      .real("damping", &damping, 0.0, 1e6, "Levenberg-Marquardt damping of the Gauss-Newton Hessian (relative to its diagonal)")
      .integer("max_iterations", &max_iterations, 1, 100000, "Ipopt iterations")
      .real("tolerance", &tolerance, 0.0, 1.0, "Ipopt convergence tolerance", true);
  return t;
}

IpoptRbfSolver::IpoptRbfSolver(const OptionMap& options) {
  init_options_ = options_.table().apply(options, "init.");
  if (!(options_.min_width < options_.max_width)) fail("ipopt: min_width must be below max_width");
  if (!init_options_.count("max_nodes")) init_options_["max_nodes"] = std::to_string(options_.nodes);
}

std::string IpoptRbfSolver::help() {
  IpoptOptions o;
  return "ipopt - bounded/constrained joint optimisation with a node budget (Ipopt):\n" + o.table().help();
}

namespace {

using Ipopt::Index;
using Ipopt::Number;

class RbfNlp : public Ipopt::TNLP {
 public:
  RbfNlp(const RbfProblem& problem, RbfNetwork& net, const IpoptOptions& o)
      : p_(problem), net_(net), o_(o), m_(net.nodes()), d_(problem.dimension()), block_(2 * d_ + 1) {
    lo_ = problem.x.colwise().minCoeff();
    hi_ = problem.x.colwise().maxCoeff();
  }

  std::vector<double> objective_history;
  std::string status = "not run";

  double constraint_value(const Number* x) const {
    double g = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) {
      const double w = x[j * block_ + 2 * d_];
      double factor = 1.0;
      if (o_.constraint == "roughness") {
        factor = 0.0;
        for (Eigen::Index k = 0; k < d_; ++k) factor += std::exp(-2.0 * x[j * block_ + d_ + k]);
      }
      g += w * w * factor;
    }
    return g;
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override {
    n = static_cast<Index>(m_ * block_);
    m = o_.constraint == "none" ? 0 : 1;
    nnz_jac = m == 0 ? 0 : (o_.constraint == "roughness" ? static_cast<Index>(m_ * (d_ + 1)) : static_cast<Index>(m_));
    nnz_h = o_.hessian == "gauss_newton" ? n * (n + 1) / 2 : 0;
    style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    for (Eigen::Index j = 0; j < m_; ++j) {
      for (Eigen::Index k = 0; k < d_; ++k) {
        const double margin = 0.1 * (hi_(k) - lo_(k));
        xl[j * block_ + k] = lo_(k) - margin, xu[j * block_ + k] = hi_(k) + margin;
        xl[j * block_ + d_ + k] = std::log(o_.min_width), xu[j * block_ + d_ + k] = std::log(o_.max_width);
      }
      xl[j * block_ + 2 * d_] = -2e19, xu[j * block_ + 2 * d_] = 2e19;
    }
    (void)n;
    if (m > 0) gl[0] = -2e19, gu[0] = bound_;
    return true;
  }

  bool get_starting_point(Index, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    for (Eigen::Index j = 0; j < m_; ++j) {
      for (Eigen::Index k = 0; k < d_; ++k) {
        x[j * block_ + k] = net_.centres(j, k);
        x[j * block_ + d_ + k] = std::clamp(std::log(net_.widths(j, k)), std::log(o_.min_width), std::log(o_.max_width));
      }
      x[j * block_ + 2 * d_] = net_.weights(j);
    }
    return true;
  }

  // The network's output at sample i (eq 4.1 with per-input widths r = exp(log r)) and, if `row` is given,
  // its derivatives with respect to every parameter [centre, log width, weight] of every node.
  double output_at(Eigen::Index i, const Number* x, double* row) const {
    double out = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) {
      const Number* b = x + j * block_;
      double z = 0.0;
      for (Eigen::Index k = 0; k < d_; ++k) {
        const double uk = (p_.x(i, k) - b[k]) / std::exp(b[d_ + k]);
        z += uk * uk;
      }
      const double ph = std::exp(-z), w = b[2 * d_];
      out += w * ph;
      if (!row) continue;
      double* g = row + j * block_;
      for (Eigen::Index k = 0; k < d_; ++k) {
        const double r = std::exp(b[d_ + k]), uk = (p_.x(i, k) - b[k]) / r;
        g[k] = w * ph * 2.0 * uk / r;
        g[d_ + k] = w * ph * 2.0 * uk * uk;
      }
      g[2 * d_] = ph;
    }
    return out;
  }

  // Residuals (cached per x) and, on request, the gradient J'r + lambda w.
  void evaluate(const Number* x, Number* gradient) {
    const Eigen::Index n = p_.size(), params = m_ * block_;
    residual_.resize(n);
    Eigen::VectorXd row(gradient ? params : 0);
    Eigen::Map<Eigen::VectorXd> grad(gradient, gradient ? params : 0);
    if (gradient) grad.setZero();
    for (Eigen::Index i = 0; i < n; ++i) {
      residual_(i) = output_at(i, x, gradient ? row.data() : nullptr) - p_.y(i);
      if (gradient) grad += residual_(i) * row;
    }
    if (gradient) {
      for (Eigen::Index j = 0; j < m_; ++j) gradient[j * block_ + 2 * d_] += o_.lambda * x[j * block_ + 2 * d_];
    }
  }

  bool eval_f(Index, const Number* x, bool, Number& obj) override {
    evaluate(x, nullptr);
    double w2 = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) w2 += x[j * block_ + 2 * d_] * x[j * block_ + 2 * d_];
    obj = 0.5 * residual_.squaredNorm() + 0.5 * o_.lambda * w2;
    return true;
  }
  bool eval_grad_f(Index, const Number* x, bool, Number* grad) override {
    evaluate(x, grad);
    return true;
  }
  bool eval_g(Index, const Number* x, bool, Index m, Number* g) override {
    if (m > 0) g[0] = constraint_value(x);
    return true;
  }
  bool eval_jac_g(Index, const Number* x, bool, Index m, Index, Index* row, Index* col, Number* values) override {
    if (m == 0) return true;
    const bool rough = o_.constraint == "roughness";
    Index at = 0;
    for (Eigen::Index j = 0; j < m_; ++j) {
      const Index w_index = static_cast<Index>(j * block_ + 2 * d_);
      if (!values) {
        row[at] = 0, col[at++] = w_index;
        if (rough)
          for (Eigen::Index k = 0; k < d_; ++k) row[at] = 0, col[at++] = static_cast<Index>(j * block_ + d_ + k);
        continue;
      }
      const double w = x[w_index];
      double factor = 1.0;
      if (rough) {
        factor = 0.0;
        for (Eigen::Index k = 0; k < d_; ++k) factor += std::exp(-2.0 * x[j * block_ + d_ + k]);
      }
      values[at++] = 2.0 * w * factor;
      if (rough)
        for (Eigen::Index k = 0; k < d_; ++k) values[at++] = -2.0 * w * w * std::exp(-2.0 * x[j * block_ + d_ + k]);
    }
    return true;
  }
  // Gauss-Newton Hessian of the Lagrangian, lower triangle: sigma (J'J + lambda I_w) plus the multiplier
  // times the weight-norm constraint's Hessian (2 I_w); the roughness constraint's curvature is left out.
  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index m, const Number* multipliers, bool, Index,
              Index* row, Index* col, Number* values) override {
    if (!values) {
      Index at = 0;
      for (Index i = 0; i < n; ++i)
        for (Index j = 0; j <= i; ++j) row[at] = i, col[at++] = j;
      return true;
    }
    const Eigen::MatrixXd jac = jacobian(x);
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    h.selfadjointView<Eigen::Lower>().rankUpdate(jac.transpose());
    // Levenberg-Marquardt damping of the Gauss-Newton matrix: nodes with little weight make J'J nearly
    // singular in their centre and width directions, and undamped Newton steps there are huge.
    const Eigen::VectorXd diag = h.diagonal();
    h.diagonal() += o_.damping * diag + Eigen::VectorXd::Constant(n, 1e-10 * diag.maxCoeff());
    h *= obj_factor;
    const double constraint_curvature = (m > 0 && o_.constraint == "weight_norm") ? 2.0 * multipliers[0] : 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) {
      const Eigen::Index w = j * block_ + 2 * d_;
      h(w, w) += obj_factor * o_.lambda + constraint_curvature;
    }
    Index at = 0;
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j <= i; ++j) values[at++] = h(i, j);
    return true;
  }

  Eigen::MatrixXd jacobian(const Number* x) const {
    const Eigen::Index n = p_.size(), params = m_ * block_;
    Eigen::MatrixXd jac(n, params);
    Eigen::VectorXd row(params);
    for (Eigen::Index i = 0; i < n; ++i) {
      output_at(i, x, row.data());
      jac.row(i) = row.transpose();
    }
    return jac;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index, Number obj, Number, Number, Number, Number, Number, Number,
                             Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    objective_history.push_back(obj);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn s, Index, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status = s == Ipopt::SUCCESS ? "success" : s == Ipopt::MAXITER_EXCEEDED ? "max_iterations" : "ipopt_status_" + std::to_string(static_cast<int>(s));
    for (Eigen::Index j = 0; j < m_; ++j) {
      for (Eigen::Index k = 0; k < d_; ++k) {
        net_.centres(j, k) = x[j * block_ + k];
        net_.widths(j, k) = std::exp(x[j * block_ + d_ + k]);
      }
      net_.weights(j) = x[j * block_ + 2 * d_];
    }
  }

  double bound_ = 0.0;

 private:
  const RbfProblem& p_;
  RbfNetwork& net_;
  const IpoptOptions& o_;
  Eigen::Index m_, d_, block_;
  Eigen::RowVectorXd lo_, hi_;
  Eigen::VectorXd residual_;
};

}  // namespace

SolverSummary IpoptRbfSolver::train(const RbfProblem& problem, RbfNetwork& net) {
  const auto start = std::chrono::steady_clock::now();
  const SolverSummary init = initial_network(options_.init, init_options_, problem, net);
  if (net.nodes() > options_.nodes) {  // keep the budget (forward selection orders nodes by importance)
    net.centres.conservativeResize(options_.nodes, Eigen::NoChange);
    net.widths.conservativeResize(options_.nodes, Eigen::NoChange);
    net.weights.conservativeResize(options_.nodes);
  }
  Ipopt::SmartPtr<RbfNlp> nlp = new RbfNlp(problem, net, options_);
  if (options_.constraint != "none") {
    std::vector<double> x0(static_cast<std::size_t>(net.nodes() * (2 * problem.dimension() + 1)));
    Ipopt::Index dummy = 0;
    nlp->get_starting_point(dummy, true, x0.data(), false, nullptr, nullptr, 0, false, nullptr);
    nlp->bound_ = options_.bound > 0 ? options_.bound : 1.5 * nlp->constraint_value(x0.data());
  }
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", std::getenv("GYROSID_IPOPT_PRINT") ? std::atoi(std::getenv("GYROSID_IPOPT_PRINT")) : 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetStringValue("hessian_approximation", options_.hessian == "gauss_newton" ? "exact" : "limited-memory");
  app->Options()->SetIntegerValue("max_iter", options_.max_iterations);
  app->Options()->SetNumericValue("tol", options_.tolerance);
  // Bounds are rarely active at the solution: start the barrier small and decrease it monotonically, so it
  // does not hold the iterates away from the least-squares minimum.
  app->Options()->SetStringValue("mu_strategy", "monotone");
  app->Options()->SetNumericValue("mu_init", 1e-8);
  if (app->Initialize() != Ipopt::Solve_Succeeded) fail("ipopt: initialisation failed");
  app->OptimizeTNLP(nlp);

  SolverSummary s;
  s.solver = "ipopt";
  s.termination = nlp->status;
  s.iterations = static_cast<int>(nlp->objective_history.size());
  s.cost_history = nlp->objective_history;
  s.nodes = static_cast<int>(net.nodes());
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.peak_rss_mb = peak_rss_mb();
  s.details = {{"init", init.to_json()}, {"constraint", options_.constraint}, {"bound", nlp->bound_}};
  return s;
}

}  // namespace gyrosid
