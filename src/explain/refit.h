// The final joint fit of a selected model on the whitened training samples: the nonlinear time constants
// (the coil's thermal lag when it was found missing, the warm-up's) by variable projection - NLopt's BOBYQA
// over log(tau) with every linear coefficient solved exactly inside - then the joint problem in Ceres
// (a Levenberg-Marquardt polish and ceres::Covariance, scaled by the residual variance). Time constants
// live in log(tau), so their intervals are asymmetric in tau.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "explain/selection.h"

namespace gyrosid::explain {

// A nonlinear scale parameter refined with the coefficients: the coil's thermal lag (term -1, tau_s) or a
// term's (a warm-up's tau_s, a hysteresis's width_c). A term's location parameter (a change point's time)
// keeps the value the selection's scan found.
struct NonlinearFit {
  int term = -1;
  std::string name;
  double value = 0.0;
  double low = 0.0, high = 0.0;  // 95 % interval (log-normal)
};

struct RefitResult {
  ModelSpec model;                 // with the refined time constants
  Eigen::VectorXd beta;            // per column of the model's design matrix (deg/h per column unit); 0 if dropped
  Eigen::VectorXd beta_sigma;      // standard deviations (0 where not computable)
  std::vector<char> kept;          // per column: identifiable
  std::vector<NonlinearFit> nonlinear;
  double residual_sigma = 0.0;     // whitened residual standard deviation, deg/h
  std::string termination;
  int iterations = 0;
  bool covariance_ok = false;
};

// The whitened RSS of a model with its nonlinear scale parameters (and the lag, if refine_lag) re-optimised
// by variable projection from their current values (at most 30 evaluations each): a profile likelihood.
struct ProfiledFit {
  double rss = 0.0;
  int nonlinear = 0;       // parameters re-optimised
  ModelSpec model;         // with them at the optimum
  bool converged = false;  // the search stopped on its tolerance, not its evaluation limit
};
ProfiledFit profiled_fit(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& model, bool refine_lag,
                         const TermScaling& scaling, const Whitener& whitener);

// `refine_lag`: the lag is a parameter (it was selected); otherwise it stays at the model's value.
// `optimised`: the model's nonlinear parameters are already at the projected optimum (a converged profile
// of this model, refine_lag alike): the variable-projection search is skipped, the polish starts there.
RefitResult refit(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& model, bool refine_lag,
                  const TermScaling& scaling, const Whitener& whitener, bool optimised = false);

}  // namespace gyrosid::explain
