#include "design/design_problem.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/parallel.h"

namespace gyrosid::design {

void QuadratureOptions::bind(OptionTable& t) {
  t.real("quadrature.max_spacing_s", &max_spacing_s, 0.0, 600.0, "objective quadrature: largest spacing", true)
      .integer("quadrature.points_per_cycle", &points_per_cycle, 4, 100, "objective quadrature: points per rate cycle")
      .integer("quadrature.relaxed_times", &relaxed_times, 2, 1000, "smooth relaxation: time nodes per segment")
      .integer("quadrature.relaxed_rates", &relaxed_rates, 2, 20, "smooth relaxation: rate nodes per time node");
}

DesignProblem::DesignProblem(const DesignContext& context, const DesignSpace& space, QuadratureOptions quadrature)
    : DesignProblem(std::vector<WeightedContext>{{&context, 1.0}}, space, quadrature) {}

void PriorOptions::bind(OptionTable& t) {
  t.real("prior.worst_share", &worst_share, 0.0, 1.0, "--prior: the share of the prior's weight whose mean objective is minimised "
                                                      "(1: the mean over all members; 0.25: the worst quarter)", true);
}

double upper_tail_mean(const std::vector<double>& values, const std::vector<double>& weights, double share) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] > values[b]; });
  const double want = share * std::accumulate(weights.begin(), weights.end(), 0.0);
  double sum = 0.0, taken = 0.0;
  for (std::size_t k : order) {
    const double w = std::min(weights[k], want - taken);
    if (w <= 0.0) break;
    sum += w * values[k], taken += w;
  }
  return sum / taken;
}

DesignProblem::DesignProblem(std::vector<WeightedContext> members, const DesignSpace& space, QuadratureOptions quadrature, PriorOptions prior)
    : members_(std::move(members)), space_(space), q_(quadrature), prior_(prior) {
  if (!(prior_.worst_share > 0.0 && prior_.worst_share <= 1.0)) fail("design: prior.worst_share must be in (0, 1], got ", prior_.worst_share);
  if (members_.empty()) fail("design: a prior over sensors needs at least one member");
  for (const auto& m : members_) {
    if (!m.context || !(m.weight > 0.0)) fail("design: every member of a prior needs a context and a positive weight");
  }
}

// The members are evaluated in parallel (each its own output; summed in order, so the same result on any number
// of threads).
template <class Observe>
double DesignProblem::mean_objective(const Observe& observe_member) const {
  std::vector<double> value(members_.size());
  const auto evaluate = [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
      const DesignContext& c = *members_[k].context;
      value[k] = c.objective(c.estimate(observe_member(c), c.objective_needs_target()), offsets_);
    }
  };
  if (members_.size() == 1) evaluate(0, 1);
  else parallel_for(static_cast<std::ptrdiff_t>(members_.size()), evaluate);
  if (prior_.worst_share < 1.0) {
    std::vector<double> weights;
    for (const auto& m : members_) weights.push_back(m.weight);
    return upper_tail_mean(value, weights, prior_.worst_share);
  }
  double sum = 0.0, weights = 0.0;
  for (std::size_t k = 0; k < members_.size(); ++k) sum += members_[k].weight * value[k], weights += members_[k].weight;
  return sum / weights;
}

Observations DesignProblem::observe_programme(const TableProfile& programme) const {
  const TableProfile all = continued(programme);
  const Quadrature q = programme_quadrature(all, q_.max_spacing_s, q_.points_per_cycle);
  return observe(all, q.times, q.weights_s, context().gyro(), context().thermal());
}

double DesignProblem::objective(const TableProfile& programme) const {
  const TableProfile all = continued(programme);
  const Quadrature q = programme_quadrature(all, q_.max_spacing_s, q_.points_per_cycle);
  return mean_objective([&](const DesignContext& c) { return observe(all, q.times, q.weights_s, c.gyro(), c.thermal()); });
}

namespace {

// Gauss-Legendre nodes on [0, 1] and weights summing to 1 (Golub-Welsch).
std::pair<std::vector<double>, std::vector<double>> unit_legendre(int n) {
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, n);
  for (int i = 1; i < n; ++i) j(i, i - 1) = j(i - 1, i) = i / std::sqrt(4.0 * i * i - 1.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(j);
  std::vector<double> x(static_cast<std::size_t>(n)), w(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    x[static_cast<std::size_t>(i)] = 0.5 * (1.0 + eig.eigenvalues()(i));
    w[static_cast<std::size_t>(i)] = eig.eigenvectors()(0, i) * eig.eigenvectors()(0, i);
  }
  return {x, w};
}

}  // namespace

double DesignProblem::smooth_objective(const SmoothProgramme& x) const {
  if (!recorded_.segments.empty()) fail("design: the smooth relaxation (ipopt) cannot continue recorded segments; use the nlopt solver");
  const TableProfile p = space_.decode_smooth(x);
  const auto [nodes, weights] = unit_legendre(q_.relaxed_rates);
  std::vector<double> times, span;
  RateRelaxation relax;
  relax.weights = weights;
  double start = 0.0;
  for (std::size_t i = 0; i < p.segments.size(); ++i) {
    const double d = p.segments[i].duration_s, h = d / q_.relaxed_times;
    const double lo = std::clamp(std::min(x.low_radps[i], x.high_radps[i]), -space_.rate_max_radps(), space_.rate_max_radps());
    const double hi = std::clamp(std::max(x.low_radps[i], x.high_radps[i]), -space_.rate_max_radps(), space_.rate_max_radps());
    std::vector<double> rates;
    for (double u : nodes) rates.push_back(lo + (hi - lo) * u);
    for (int k = 0; k < q_.relaxed_times; ++k) {
      times.push_back(start + (k + 0.5) * h);
      span.push_back(h);
      relax.rate_nodes_radps.push_back(rates);
    }
    start += d;
  }
  return mean_objective([&](const DesignContext& c) { return observe(p, times, span, c.gyro(), c.thermal(), &relax); });
}

}  // namespace gyrosid::design
