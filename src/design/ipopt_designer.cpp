// The `ipopt` design solver: Ipopt's interior-point method on the smooth relaxation of the programme
// (design_space.h): variables start temperature, segment durations, end temperatures and rate bounds, each
// scaled to O(1); linear constraints  sum d_i = budget,  |T_i - T_{i-1}| <= r d_i,  low_i <= high_i;
// gradients by forward differences, a limited-memory Hessian. The relaxed optimum is rounded to whole rate
// cycles of the preferred period (design_space.h) and scored exactly. An iteration is one interior-point
// iteration; its cost is the relaxed objective.
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>

#include <cmath>

#include "core/error.h"
#include "core/packed_layout.h"
#include "core/progress.h"
#include "core/random.h"
#include "design/design_solver.h"
#include "solvers/common/terminations.h"

namespace gyrosid::design {

OptionTable IpoptDesignOptions::table() {
  OptionTable t("ipopt");
  t.integer("max_iterations", &max_iterations, 1, 100000, "interior-point iterations per start")
      .real("tolerance", &tolerance, 0.0, 1.0, "Ipopt convergence tolerance", true)
      .real("gradient_step", &gradient_step, 0.0, 0.1, "forward-difference step on the O(1)-scaled variables", true)
      .integer("starts", &starts, 1, 100, "starts: the initial programme, then seeded perturbations of it")
      .integer("print_level", &print_level, 0, 12, "Ipopt's own console output (0: silent)");
  return t;
}

std::string IpoptDesignOptions::validate() const { return ""; }

namespace {

using Ipopt::Index;
using Ipopt::Number;

// The scaled variables z = [T_0 / 50 C; durations / budget; end temperatures / 50 C; low and high rates /
// rate bound] (each per segment K long) and the constraint rows g = [sum of durations; per segment its heating
// and its cooling ramp; per segment low - high], as named spans.
struct RelaxedLayout {
  explicit RelaxedLayout(int k) {
    SpanPacker z, g;
    start = z.take(1), duration = z.take(k), end = z.take(k), low = z.take(k), high = z.take(k);
    variables = z.size();
    budget_row = g.take(1), ramp_rows = g.take(2 * k), order_rows = g.take(k);
    constraints = g.size();
  }
  Index heating_row(int i) const { return static_cast<Index>(ramp_rows.at(2 * i)); }
  Index cooling_row(int i) const { return static_cast<Index>(ramp_rows.at(2 * i + 1)); }
  // The chamber temperature segment i starts from: T_0, or the previous segment's end.
  Index previous_end(int i) const { return static_cast<Index>(i == 0 ? start.offset : end.at(i - 1)); }

  Span start, duration, end, low, high, budget_row, ramp_rows, order_rows;
  Eigen::Index variables = 0, constraints = 0;
};

class RelaxedNlp : public Ipopt::TNLP {
 public:
  RelaxedNlp(const DesignProblem& problem, const IpoptDesignOptions& o, SolveMonitor& monitor, Progress& progress,
             std::vector<double> start)
      : p_(problem), s_(problem.space()), o_(o), monitor_(monitor), progress_(progress), k_(s_.options().segments), at_(k_),
        start_(std::move(start)) {}

  Ipopt::SolverReturn status = Ipopt::UNASSIGNED;
  std::vector<double> solution;
  int iterations = 0;

  static constexpr double kTempScale = 50.0;
  // Scaled variables <-> the smooth programme.
  SmoothProgramme unscale(const Number* z) const {
    SmoothProgramme x;
    x.start_c = z[at_.start.offset] * kTempScale;
    for (int i = 0; i < k_; ++i) {
      x.duration_s.push_back(z[at_.duration.at(i)] * s_.budget_s());
      x.end_c.push_back(z[at_.end.at(i)] * kTempScale);
      x.low_radps.push_back(z[at_.low.at(i)] * s_.rate_max_radps());
      x.high_radps.push_back(z[at_.high.at(i)] * s_.rate_max_radps());
    }
    return x;
  }
  static std::vector<double> scale(const SmoothProgramme& x, const DesignSpace& s) {
    const int k = static_cast<int>(x.duration_s.size());
    const RelaxedLayout at(k);
    std::vector<double> z(static_cast<std::size_t>(at.variables));
    const auto put = [&](Eigen::Index index, double value) { z[static_cast<std::size_t>(index)] = value; };
    put(at.start.offset, x.start_c / kTempScale);
    for (int i = 0; i < k; ++i) {
      const auto u = static_cast<std::size_t>(i);
      put(at.duration.at(i), x.duration_s[u] / s.budget_s());
      put(at.end.at(i), x.end_c[u] / kTempScale);
      put(at.low.at(i), x.low_radps[u] / s.rate_max_radps());
      put(at.high.at(i), x.high_radps[u] / s.rate_max_radps());
    }
    return z;
  }

  double value(const Number* z) {
    monitor_.evaluation();
    return p_.smooth_objective(unscale(z));
  }

  bool get_nlp_info(Index& n_vars, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override {
    n_vars = static_cast<Index>(at_.variables);
    m = static_cast<Index>(at_.constraints);
    nnz_jac = k_ + 6 * k_ + 2 * k_;  // sum d; two ramp rows of 3 entries per segment; low - high
    nnz_h = 0;
    style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index, Number* lo, Number* hi, Index, Number* gl, Number* gu) override {
    lo[at_.start.offset] = s_.temp_lo() / kTempScale, hi[at_.start.offset] = s_.temp_hi() / kTempScale;
    for (int i = 0; i < k_; ++i) {
      lo[at_.duration.at(i)] = s_.options().min_share, hi[at_.duration.at(i)] = 1.0;
      lo[at_.end.at(i)] = s_.temp_lo() / kTempScale, hi[at_.end.at(i)] = s_.temp_hi() / kTempScale;
      lo[at_.low.at(i)] = lo[at_.high.at(i)] = -1.0;
      hi[at_.low.at(i)] = hi[at_.high.at(i)] = 1.0;
    }
    gl[at_.budget_row.offset] = gu[at_.budget_row.offset] = 1.0;
    for (Eigen::Index j = at_.ramp_rows.offset; j < at_.constraints; ++j) gl[j] = -2e19, gu[j] = 0.0;
    return true;
  }

  bool get_starting_point(Index, bool, Number* z, bool, Number*, Number*, Index, bool, Number*) override {
    std::copy(start_.begin(), start_.end(), z);
    return true;
  }

  bool eval_f(Index, const Number* z, bool, Number& obj) override {
    obj = value(z);
    return std::isfinite(obj);
  }

  bool eval_grad_f(Index nv, const Number* z, bool, Number* grad) override {
    std::vector<double> x(z, z + nv);
    const double f0 = value(z);
    for (Index i = 0; i < nv; ++i) {
      const double h = o_.gradient_step;
      x[static_cast<std::size_t>(i)] = z[i] + h;
      grad[i] = (value(x.data()) - f0) / h;
      x[static_cast<std::size_t>(i)] = z[i];
    }
    return true;
  }

  // The ramp-rate constants in scaled units: -c_cool d~ <= dT~ <= c_heat d~, c = r B / (60 T_s).
  double ramp(bool heating) const { return s_.options().chamber.limit_c_per_min(heating) * s_.budget_s() / 60.0 / kTempScale; }

  bool eval_g(Index, const Number* z, bool, Index, Number* g) override {
    double& budget = g[at_.budget_row.offset];
    budget = 0.0;
    for (int i = 0; i < k_; ++i) budget += z[at_.duration.at(i)];
    for (int i = 0; i < k_; ++i) {
      const double step = z[at_.end.at(i)] - z[at_.previous_end(i)], duration = z[at_.duration.at(i)];
      g[at_.heating_row(i)] = step - ramp(true) * duration;
      g[at_.cooling_row(i)] = -step - ramp(false) * duration;
      g[at_.order_rows.at(i)] = z[at_.low.at(i)] - z[at_.high.at(i)];
    }
    return true;
  }

  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index* row, Index* col, Number* v) override {
    Index at = 0;
    auto put = [&](Eigen::Index r, Eigen::Index c, double value) {
      if (v) v[at++] = value;
      else row[at] = static_cast<Index>(r), col[at++] = static_cast<Index>(c);
    };
    for (int i = 0; i < k_; ++i) put(at_.budget_row.offset, at_.duration.at(i), 1.0);
    for (int i = 0; i < k_; ++i) {
      for (int sign : {1, -1}) {
        const Index r = sign > 0 ? at_.heating_row(i) : at_.cooling_row(i);
        put(r, at_.end.at(i), sign);
        put(r, at_.previous_end(i), -sign);
        put(r, at_.duration.at(i), -ramp(sign > 0));
      }
      put(at_.order_rows.at(i), at_.low.at(i), 1.0);
      put(at_.order_rows.at(i), at_.high.at(i), -1.0);
    }
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index, Number obj, Number, Number, Number, Number, Number, Number,
                             Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    monitor_.iteration(obj);
    progress_.update(static_cast<std::size_t>(++iterations));
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn s, Index nv, const Number* z, const Number*, const Number*, Index, const Number*,
                         const Number*, Number, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    status = s;
    solution.assign(z, z + nv);
  }

 private:
  const DesignProblem& p_;
  const DesignSpace& s_;
  const IpoptDesignOptions& o_;
  SolveMonitor& monitor_;
  Progress& progress_;
  int k_;
  RelaxedLayout at_;
  std::vector<double> start_;
};

}  // namespace

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SmoothProgramme, start_c, duration_s, end_c, low_radps, high_radps)

IpoptDesigner::StartResult IpoptDesigner::run_start(const DesignProblem& problem, SolveMonitor& monitor, Progress& progress,
                                                    std::vector<double> z, const std::string& key) const {
  StartResult r;
  // A finished start is a checkpoint: on resume its history, evaluations and solution are taken as saved.
  if (const nlohmann::json& saved = checkpoint_ ? checkpoint_->record(key) : nlohmann::json(); !saved.is_null()) {
    for (const double value : saved_numbers(saved.at("history"))) monitor.iteration(value);
    monitor.evaluation(saved.at("evaluations").get<int>());
    r.status = saved.at("status").get<int>();
    r.iterations = saved.at("iterations").get<int>();
    if (saved.contains("solution")) from_json(saved.at("solution"), r.solution);
    progress.update(static_cast<std::size_t>(monitor.history().size()));
    return r;
  }
  const std::size_t first_iteration = monitor.history().size();
  const int first_evaluation = monitor.evaluations();
  Ipopt::SmartPtr<RelaxedNlp> nlp = new RelaxedNlp(problem, o_, monitor, progress, std::move(z));
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", o_.print_level);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  app->Options()->SetIntegerValue("max_iter", o_.max_iterations);
  app->Options()->SetNumericValue("tol", o_.tolerance);
  app->Options()->SetNumericValue("acceptable_tol", 10.0 * o_.tolerance);
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  if (app->Initialize() != Ipopt::Solve_Succeeded) fail("ipopt design: Ipopt initialisation failed");
  app->OptimizeTNLP(nlp);
  r.status = static_cast<int>(nlp->status), r.iterations = nlp->iterations;
  if (!nlp->solution.empty()) r.solution = nlp->unscale(nlp->solution.data());
  if (checkpoint_) {
    nlohmann::json j = {{"history", std::vector<double>(monitor.history().begin() + static_cast<std::ptrdiff_t>(first_iteration), monitor.history().end())},
                        {"evaluations", monitor.evaluations() - first_evaluation}, {"status", static_cast<int>(r.status)}, {"iterations", r.iterations}};
    if (!r.solution.duration_s.empty()) to_json(j["solution"], r.solution);
    checkpoint_->save_record(key, std::move(j));
  }
  return r;
}

SolveOutcome IpoptDesigner::solve(const DesignProblem& problem, TableProfile& best, SolveMonitor& monitor) {
  const DesignSpace& space = problem.space();
  const std::vector<double> base = RelaxedNlp::scale(space.smooth_of(best), space);
  Progress progress("design (ipopt)", static_cast<std::size_t>(o_.max_iterations * o_.starts));
  double best_value = problem.objective(best);
  const double initial_value = best_value;
  Termination termination = Termination::failed;
  std::string message = "no start finished";
  nlohmann::json runs = nlohmann::json::array();
  RandomStream random(seed_, "design/ipopt/starts");
  for (int start = 0; start < o_.starts; ++start) {
    std::vector<double> z = base;
    if (start > 0) {
      for (double& v : z) v += 0.15 * (2.0 * random.uniform() - 1.0);
    }
    const StartResult r = run_start(problem, monitor, progress, std::move(z), str_cat("ipopt/start/", start));
    if (r.solution.duration_s.empty()) continue;
    const TableProfile rounded = space.decode_smooth(r.solution);
    const double exact = problem.objective(rounded);
    runs.push_back({{"start", start}, {"status", r.status}, {"iterations", r.iterations}, {"exact_objective", exact}});
    if (start == 0 || exact < best_value) {
      termination = termination_of(static_cast<Ipopt::SolverReturn>(r.status));
      message = str_cat("Ipopt status ", r.status, " (start ", start, ")");
    }
    if (exact < best_value) best = rounded, best_value = exact;
  }
  progress.finish();
  return {termination, message, {{"starts", runs}, {"initial_objective", initial_value}}};
}

}  // namespace gyrosid::design
