#include "solvers/ipopt/ipopt_solver.h"

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>

#include <cmath>

#include "core/error.h"
#include "solvers/ceres/ceres_solver.h"
#include "solvers/common/ipopt_support.h"
#include "solvers/common/terminations.h"

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
      .real("tolerance", &tolerance, 0.0, 1.0, "Ipopt convergence tolerance", true)
      .integer("print_level", &print_level, 0, 12, "Ipopt's own console output (0: silent)")
      .passthrough("init.", &init_options, "an option of the init solver (max_nodes defaults to nodes)");
  return t;
}

std::string IpoptOptions::validate() const {
  if (!(min_width < max_width)) return "min_width must be below max_width";
  if (bound > 0 && constraint == "none") return "bound is set but constraint=none";
  return check_init(init, init_options);
}

IpoptRbfSolver::IpoptRbfSolver(Options options) : WithOptions(std::move(options)) {
  if (!o_.init_options.count("max_nodes")) o_.init_options["max_nodes"] = std::to_string(o_.nodes);
}

namespace {

using Ipopt::Index;
using Ipopt::Number;

class RbfNlp : public Ipopt::TNLP {
 public:
  RbfNlp(const RbfProblem& problem, RbfNetwork& net, const IpoptOptions& o, SolveMonitor& monitor)
      : p_(problem), net_(net), o_(o), monitor_(monitor), m_(net.nodes()), d_(problem.dimension()),
        block_(NodeBlock<double>::size(d_)) {
    lo_ = problem.x.colwise().minCoeff();
    hi_ = problem.x.colwise().maxCoeff();
  }

  Ipopt::SolverReturn status = Ipopt::UNASSIGNED;
  double bound_ = 0.0;

  // Node j's packed block inside Ipopt's variable vector x (NodeBlock layout [c, log r, w]).
  NodeBlock<const double> node(const Number* x, Eigen::Index j) const { return {x + j * block_, d_}; }
  NodeBlock<double> node(Number* x, Eigen::Index j) const { return {x + j * block_, d_}; }
  Index weight_index(Eigen::Index j) const { return static_cast<Index>(j * block_ + 2 * d_); }
  Index log_width_index(Eigen::Index j, Eigen::Index k) const { return static_cast<Index>(j * block_ + d_ + k); }

  // The constraint's per-node factor: 1 (weight norm) or sum_k 1/r_k^2 (roughness).
  double roughness_factor(NodeBlock<const double> b) const {
    if (o_.constraint != "roughness") return 1.0;
    double factor = 0.0;
    for (Eigen::Index k = 0; k < d_; ++k) factor += std::exp(-2.0 * b.log_width()[k]);
    return factor;
  }
  double constraint_value(const Number* x) const {
    double g = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) g += node(x, j).weight() * node(x, j).weight() * roughness_factor(node(x, j));
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

  bool get_bounds_info(Index, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    for (Eigen::Index j = 0; j < m_; ++j) {
      const NodeBlock<double> lower = node(xl, j), upper = node(xu, j);
      for (Eigen::Index k = 0; k < d_; ++k) {
        const double margin = 0.1 * (hi_(k) - lo_(k));
        lower.centre()[k] = lo_(k) - margin, upper.centre()[k] = hi_(k) + margin;
        lower.log_width()[k] = std::log(o_.min_width), upper.log_width()[k] = std::log(o_.max_width);
      }
      lower.weight() = -2e19, upper.weight() = 2e19;
    }
    if (m > 0) gl[0] = -2e19, gu[0] = bound_;
    return true;
  }

  bool get_starting_point(Index, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    for (Eigen::Index j = 0; j < m_; ++j) {
      net_.pack_node(j, node(x, j).data);
      for (Eigen::Index k = 0; k < d_; ++k) {
        double& rho = node(x, j).log_width()[k];
        rho = std::clamp(rho, std::log(o_.min_width), std::log(o_.max_width));
      }
    }
    return true;
  }

  // The network's output at sample i (eq 4.1) and, if `row` is given, its gradient by every parameter.
  double output_at(Eigen::Index i, const Number* x, double* row) const {
    const Eigen::RowVectorXd xi = p_.x.row(i);
    double out = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) out += node_output(xi.data(), node(x, j), row ? row + j * block_ : nullptr);
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
      for (Eigen::Index j = 0; j < m_; ++j) gradient[weight_index(j)] += o_.lambda * node(x, j).weight();
    }
  }

  bool eval_f(Index, const Number* x, bool, Number& obj) override {
    evaluate(x, nullptr);
    monitor_.evaluation();
    double w2 = 0.0;
    for (Eigen::Index j = 0; j < m_; ++j) w2 += node(x, j).weight() * node(x, j).weight();
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
      if (!values) {
        row[at] = 0, col[at++] = weight_index(j);
        if (rough)
          for (Eigen::Index k = 0; k < d_; ++k) row[at] = 0, col[at++] = log_width_index(j, k);
        continue;
      }
      const NodeBlock<const double> b = node(x, j);
      values[at++] = 2.0 * b.weight() * roughness_factor(b);
      if (rough)
        for (Eigen::Index k = 0; k < d_; ++k) values[at++] = -2.0 * b.weight() * b.weight() * std::exp(-2.0 * b.log_width()[k]);
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
    for (Eigen::Index j = 0; j < m_; ++j) h(weight_index(j), weight_index(j)) += obj_factor * o_.lambda + constraint_curvature;
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
    monitor_.iteration(obj);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn s, Index, const Number* x, const Number*, const Number*, Index,
                         const Number*, const Number*, Number, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    status = s;
    for (Eigen::Index j = 0; j < m_; ++j) net_.unpack_node(j, node(x, j).data);
  }

 private:
  const RbfProblem& p_;
  RbfNetwork& net_;
  const IpoptOptions& o_;
  SolveMonitor& monitor_;
  Eigen::Index m_, d_, block_;
  Eigen::RowVectorXd lo_, hi_;
  Eigen::VectorXd residual_;
};

}  // namespace

SolveOutcome IpoptRbfSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  const SolveSummary init = initial_network(o_.init, o_.init_options, problem, net);
  if (net.nodes() > o_.nodes) {  // keep the budget (forward selection orders nodes by importance)
    net.centres.conservativeResize(o_.nodes, Eigen::NoChange);
    net.widths.conservativeResize(o_.nodes, Eigen::NoChange);
    net.weights.conservativeResize(o_.nodes);
  }
  Ipopt::SmartPtr<RbfNlp> nlp = new RbfNlp(problem, net, o_, monitor);
  if (o_.constraint != "none") {
    std::vector<double> x0(static_cast<std::size_t>(net.nodes() * NodeBlock<double>::size(problem.dimension())));
    nlp->get_starting_point(0, true, x0.data(), false, nullptr, nullptr, 0, false, nullptr);
    nlp->bound_ = o_.bound > 0 ? o_.bound : 1.5 * nlp->constraint_value(x0.data());
  }
  const Ipopt::ApplicationReturnStatus status =
      solve_with_ipopt(nlp, {o_.print_level, o_.hessian == "gauss_newton", o_.max_iterations, o_.tolerance}, "ipopt");
  return {termination_of(nlp->status), str_cat("Ipopt application status ", static_cast<int>(status)),
          {{"init", init}, {"constraint", o_.constraint}, {"bound", nlp->bound_}}};
}

}  // namespace gyrosid
