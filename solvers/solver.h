// One interface for every RBF training back-end (solvers/<name>/), chosen by name, compared on equal terms.
//
//   auto solver = make_solver("ols", {{"criterion", "bic"}, {"width", "0.3"}});
//   RbfNetwork net = ...;  SolverSummary s = solver->train(problem, net);
//
// Every solve returns a SolverSummary (termination, iterations, cost history, nodes, time) that is written
// with the model.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "model/dataset.h"
#include "model/normalizer.h"
#include "core/solve_summary.h"
#include "model/rbf_network.h"
#include "solvers/common/options.h"

namespace gyrosid {

// The training problem in the network's own coordinates: normalised inputs, target scaled to unit RMS.
struct RbfProblem {
  std::vector<std::string> features;
  ModelTarget target = ModelTarget::error;
  Normalizer normalizer;
  Eigen::MatrixXd x;     // N x d, normalised
  Eigen::VectorXd y;     // N, target / y_scale
  double y_scale = 1.0;  // rad/s per unit of y

  Eigen::Index size() const { return x.rows(); }
  Eigen::Index dimension() const { return x.cols(); }
  RbfNetwork empty_network() const;
  // Converts a network fitted to the scaled target (weights in y units) to rad/s, in place.
  void unscale(RbfNetwork& net) const;
};

RbfProblem make_rbf_problem(const Dataset& data, NormalizationKind normalization);

struct SolverSummary {
  std::string solver;
  std::string termination;
  int iterations = 0;
  std::vector<double> cost_history;  // per selection step (criterion) or per iteration (cost)
  int nodes = 0;
  double time_s = 0.0;
  double peak_rss_mb = 0.0;
  nlohmann::json details = nlohmann::json::object();
  nlohmann::json to_json() const;
};

class RbfSolver {
 public:
  virtual ~RbfSolver() = default;
  virtual std::string_view name() const = 0;
  // Fits `net` to the problem (net arrives empty, with the problem's normaliser).
  virtual SolverSummary train(const RbfProblem& problem, RbfNetwork& net) = 0;
};

std::unique_ptr<RbfSolver> make_solver(const std::string& name, const OptionMap& options);
std::vector<std::string> solver_names();
std::string solver_help(const std::string& name);  // the solver's options with defaults, ranges, meanings

}  // namespace gyrosid
