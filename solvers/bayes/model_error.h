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
//          is nearly constant over a run while white noise averages down), with mean residual e_r and
//          c_rr = h_r' A_k^-1 h_r + v_r, the variance of e_r were the model class right (the estimate's plus
//          the noise's run mean, white + Gauss-Markov; a random walk's level is pinned by the neighbouring
//          samples and left out);
//   excess: per fold the weighted mean of e_r^2 - c_rr (weights 1/c_rr^2), averaged over the folds;
//   test:   kept when it exceeds twice its standard error were the model class right, from the run means'
//          joint covariance C = H A_k^-1 H' + V (cov(e_r^2, e_s^2) = 2 c_rs^2 for Gaussian e). The spread of
//          the excess over the folds is no such measure: a real misfit differs from fold to fold (sensor C's
//          scale-factor ripple grows with the rate: 726 +- 366 (deg/h)^2 over its staircase's 13 levels at
//          1 deg/h white noise, 1.98 spreads, was discarded, and the band covered none of the held-out errors);
//   s_m^2:  the excess; over level folds a quarter of it - a left-out level is predicted one spacing from
//          the nearest level kept, a point between levels is at most half a spacing from one, and a misfit
//          whose rms grows linearly with that distance has a quarter of the variance there (a smooth misfit
//          grows faster, so this errs large).
//
// The predictive variance becomes h' P h + s_m^2 (model/weight_posterior.h).
#pragma once

#include <string>
#include <vector>

#include "solvers/bayes/bayes_fit.h"

namespace gyrosid {

struct ModelErrorEstimate {
  double variance = 0.0;        // s_m^2, y units^2 (0 when not significant)
  double mean_excess = 0.0;     // the estimate before the significance test
  double standard_error = 0.0;  // its standard error were the model class right
  int folds = 0;
  std::string fold_kind;        // "levels of input k" or "time blocks"
  std::string describe(double to_dph) const;
};

// Covariance of the noise's run means (white + Gauss-Markov, the model's units), runs: each run's sample
// times, runs disjoint and in time order. Between runs r < s the Gauss-Markov double sum factorises,
// sum_ij exp(-(t_j - t_i)/tau) = a_r exp(-(t_s0 - t_r1)/tau) b_s with a_r = sum_i exp(-(t_r1 - t_i)/tau),
// b_s = sum_j exp(-(t_j - t_s0)/tau) (t_r1: run r's last sample, t_s0: run s's first); within a run the
// double sum is a recursion over consecutive samples: O(R^2 + sum n_r).
// (A random walk's level is pinned by the neighbouring samples; it is left out.)
Eigen::MatrixXd run_mean_noise_covariance(const std::vector<std::vector<double>>& runs, const NoiseModel& m);

// `fit` is the final fit of `problem` (its noise model, or white with precision exp(log_beta)); t_s the
// sample times (every sample).
ModelErrorEstimate model_error_by_cv(const BayesProblem& problem, const BayesFit& fit, const std::vector<double>& t_s);

}  // namespace gyrosid
