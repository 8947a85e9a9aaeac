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
//   null:   its standard error were the model class right, from the run means' joint covariance C = H A_k^-1
//          H' + V (cov(e_r^2, e_s^2) = 2 c_rs^2 for Gaussian e). Reported, no longer a gate: the old rule
//          (kept only above 2 standard errors) dropped misfits of 1.2-1.3 standard errors that cost the band
//          7-25 points of coverage (sensor C's sine sweep at 1 deg/h: 0.0255 +- 0.0196 (deg/h)^2, coverage
//          0.876; `bayes` on the reference white 10 seed 3: 1.32 +- 1.07, coverage 0.683);
//   groups: runs (above), or cells of half a width per input (option model_error_groups; measured no more
//          resolving on those two recordings, so not the default);
//   s_m^2:  the excess, never negative, whether or not significant; over level folds a quarter of it - a left-out level is predicted one spacing from
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

enum class ModelErrorGroups { cells, runs };

struct ModelErrorOptions {
  int blocks = 10;                                 // time blocks (folds) when no input is recorded at levels
  ModelErrorGroups groups = ModelErrorGroups::runs;  // how a fold's samples are averaged (groups_of)
};

struct ModelErrorEstimate {
  double variance = 0.0;        // s_m^2, y units^2: reach x the excess, never negative
  double mean_excess = 0.0;     // the estimate before the significance test
  double standard_error = 0.0;  // its standard error were the model class right
  double reach = 1.0;           // the share of the excess taken as the misfit between the folds' inputs
  int folds = 0;
  std::string fold_kind;        // "levels of input k" or "time blocks"
  double cv_mse = 0.0;          // mean squared residual of every fold's samples predicted from the other folds,
                                // y units^2: noise plus misfit plus the estimate's variance, comparable between
                                // models fitted to the same recording (same folds)
  std::string describe(double to_dph) const;
};

// Covariance of the noise's group means (white + Gauss-Markov, the model's units), groups: each group's sample
// times in time order; groups may interleave in time (a cell of the input grid is visited again and again).
// The Gauss-Markov double sums sum_ij exp(-|t_i - t_j|/tau) come from one sweep over all samples in time
// order, O(R sum n_r) (no sample x sample matrix). (A random walk's level is pinned by the neighbouring
// samples; it is left out.)
Eigen::MatrixXd group_mean_noise_covariance(const std::vector<std::vector<double>>& groups, const NoiseModel& m);

// `fit` is the final fit of `problem` (its noise model, or white with precision exp(log_beta)); t_s the
// sample times (every sample).
ModelErrorEstimate model_error_by_cv(const BayesProblem& problem, const BayesFit& fit, const std::vector<double>& t_s,
                                     const ModelErrorOptions& options = {});

}  // namespace gyrosid
