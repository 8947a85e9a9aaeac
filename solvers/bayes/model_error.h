// Model-class error the data can reveal (issue 11): the posterior of a Bayesian RBF (or hybrid) is exact only
// if the truth is a draw from its prior under its noise model. When it is not - a scale-factor ripple
// between the rate levels of a staircase, a shape the physics lacks - the predictive sigma knows nothing of
// the misfit. This estimates a variance s_m^2 of that misfit by cross-validation, with the hyper-parameters
// (widths, alpha, noise) held at the fit's values:
//
//   folds: the levels of an input recorded at discrete levels (predicting a level from the others mimics
//          predicting between levels), else K contiguous blocks in time;
//   per fold k: the posterior mean m_k and covariance A_k^-1 from the other samples (white noise: the full
//          Gram matrix minus the fold's, O(N (M+P)^2) once; coloured: the other samples whitened anew by
//          the Kalman filter across the gap, O(N (M+P)^2) per fold; no N x N matrix);
//   runs: the fold's samples split into runs over which the inputs move less than half a width (the misfit
//          is nearly constant over a run while white noise averages down), with mean residual e_r,
//          the estimate's variance a_r = h_r' A_k^-1 h_r and the noise variance of the run mean v_r
//          (white + Gauss-Markov; a random walk's level is pinned by the neighbouring samples and left out);
//   s_m^2 = mean over folds of the weighted mean of e_r^2 - a_r - v_r (weights 1/(a_r + v_r)^2), kept when
//          it exceeds twice its standard error over the folds, else 0.
//
// The predictive variance becomes h' P h + s_m^2 (model/weight_posterior.h). A level fold interpolates
// over twice the level spacing, so on a staircase the estimate errs on the large side.
#pragma once

#include <string>
#include <vector>

#include "solvers/bayes/bayes_fit.h"

namespace gyrosid {

struct ModelErrorEstimate {
  double variance = 0.0;        // s_m^2, y units^2 (0 when not significant)
  double mean_excess = 0.0;     // the estimate before the significance test
  double standard_error = 0.0;  // its standard error over the folds
  int folds = 0;
  std::string fold_kind;        // "levels of input k" or "time blocks"
  std::string describe(double to_dph) const;
};

// `fit` is the final fit of `problem` (its noise model, or white with precision exp(log_beta)); t_s the
// sample times (every sample).
ModelErrorEstimate model_error_by_cv(const BayesProblem& problem, const BayesFit& fit, const std::vector<double>& t_s);

}  // namespace gyrosid
