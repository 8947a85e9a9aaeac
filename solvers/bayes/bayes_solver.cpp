#include "solvers/bayes/bayes_solver.h"

#include "core/recording.h"
#include "core/units.h"

namespace gyrosid {

OptionTable BayesOptions::table() {
  OptionTable t("bayes");
  bind(t);
  return t;
}

SolveOutcome BayesRbfSolver::fit(const RbfProblem& problem, RbfNetwork& net, SolveMonitor& monitor) {
  BayesProblem p;
  p.x = problem.x;
  p.y = problem.y;
  p.fixed = Eigen::MatrixXd::Ones(problem.size(), 1);
  p.t_s = problem.t_s;
  p.report_scale = units::radps_to_dph(problem.y_scale);
  if (o_.noise == "given") p.given_noise = given_noise_model(o_, median_sample_interval(p.t_s), problem.y_scale);
  const BayesFit f = fit_bayes(p, o_, monitor);
  const Eigen::Index m = f.centres.rows();
  net.centres = f.centres;
  net.widths = f.widths.replicate(m, 1);
  net.weights = f.rbf_weights;
  net.bias = f.fixed_weights(0);
  net.weight_posterior = WeightPosterior::of_covariance(f.covariance, f.noise_sigma);
  net.weight_posterior->model_error_radps = std::sqrt(f.model_error_var);
  if (f.noise) net.weight_posterior->noise_model = scaled(*f.noise, units::radps_to_dph(problem.y_scale)).to_json();
  return {f.termination, f.message, f.details(problem.y_scale)};
}

}  // namespace gyrosid
