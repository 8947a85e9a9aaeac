// The residual's noise model for whitening: white noise plus a rate random walk plus a Gauss-Markov process
// (the shapes of an Allan-deviation curve: slope -1/2, +1/2, and a bump standing in for bias instability or
// any correlated drift), as a state-space model
//
//   e_t = w_t + g_t + v_t,   w_t = w_{t-1} + eta_t (var q),   g_t = phi g_{t-1} + zeta_t,   v_t white (var r),
//
// projected from the residual's identified composite model (noise/identify.h: the one noise estimator of
// every command) over the band the identification claims. The whitener runs the
// Kalman filter along the chosen samples in time order, propagating the state over each interval - gaps in
// the sampling (bursts, held-out blocks) included: the random walk grows and the Gauss-Markov process decays
// over them. The standardised innovations of the data (and, with the same data-independent gains, of every
// regressor column) are white with unit variance under the model - generalised least squares without an
// N x N covariance. The random walk starts diffuse: the overall level is never information. Coloured noise is thereby noise: a slow wander is not mistaken for ageing or a
// temperature effect, and structure that is real must show beyond it.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <vector>

#include "noise/composite.h"
#include "noise/identify.h"

namespace gyrosid {

struct NoiseModel {
  double dt_s = 1.0;
  double white_var = 1.0;  // per-sample variance of the white part
  double rw_q = 0.0;       // per-sample increment variance of the random walk
  double gm_var = 0.0;     // stationary variance of the Gauss-Markov part
  double gm_tau_s = 0.0;   // its correlation time

  int parameters() const { return 1 + (rw_q > 0 ? 1 : 0) + (gm_var > 0 ? 2 : 0); }
  double allan_variance(double tau_s) const;   // the model's Allan variance at averaging time tau
  double stationary_sigma() const;             // sqrt(white + Gauss-Markov variance), per sample
  nlohmann::json to_json() const;              // in the residual's units (deg/h)
  static NoiseModel from_json(const nlohmann::json& j);  // what to_json wrote
};

// Runs: the rows (sample indices, ascending) split wherever the index jumps or the segment id changes.
std::vector<std::vector<Eigen::Index>> contiguous_runs(const std::vector<Eigen::Index>& rows, const std::vector<int>& segment);

// The whitening family's member closest to an identified composite (model in the residual's units, per
// sample at dt_s): white + random walk + one Gauss-Markov process fitted to the composite's Allan variance at
// log-spaced taus over [tau_low, tau_high] (equal relative weights). Exact when the composite is of that
// form; quantization and a filter term, which act only at the shortest taus, are left out.
NoiseModel whitening_model(const CompositeNoise& model, double dt_s, double tau_low_s, double tau_high_s);

// Where a whitening model comes from. identified: the noise of x over its longest run by the one estimator
// (identify_noise, at most two Gauss-Markov terms), projected onto the whitening family - calibrate's noise.
// gauss_markov_start: the family itself fitted to the run's Allan curve (white + random walk + one
// Gauss-Markov by quasi-likelihood NNLS) - explain's start for its likelihood search. explain keeps it because
// its residuals may still hold a step or a trend the selection has yet to find: the composite estimator reads
// a step's Allan signature as a rate random walk, and a random-walk start lets the whitening absorb the step
// (a half-sigma step was missed so); telling the two apart in one likelihood comparison is issue 34's work.
enum class NoiseStart { identified, gauss_markov_start };

// The whitening model of x from its longest run; white noise only when no run has 500 samples (the variance
// over all runs).
// identified: when not null and the start is identified, the identification itself.
NoiseModel fit_noise_model(const Eigen::VectorXd& x, const std::vector<std::vector<Eigen::Index>>& runs, double dt_s,
                           NoiseStart start = NoiseStart::identified, NoiseIdentification* identified = nullptr);

// How the random-walk state starts: diffuse (its level is never information - explain's residual tests), or
// at zero with the first sample (a calibration: the level at the start of the recording is the turn-on bias,
// estimated as a constant, and the walk wanders from it - as noise/processes.h generates it).
enum class RandomWalkStart { diffuse, zero };

class Whitener {
 public:
  // rows: the samples to whiten, ascending; t_s: every sample's time.
  Whitener(NoiseModel model, std::vector<Eigen::Index> rows, const std::vector<double>& t_s,
           RandomWalkStart start = RandomWalkStart::diffuse);
  Eigen::MatrixXd apply(const Eigen::MatrixXd& x) const;  // x has one row per sample of the recording
  // The adjoint: W' z for z with one row per whitened sample (rows().size()), returned with one row per
  // sample of the recording (zero where not whitened) - for gradients through the whitening.
  Eigen::MatrixXd apply_transpose(const Eigen::MatrixXd& z, Eigen::Index recording_rows) const;
  const std::vector<Eigen::Index>& rows() const { return rows_; }
  const NoiseModel& model() const { return model_; }
  // sum_t log S_t (innovation variances): the determinant term of the Gaussian log-likelihood.
  double log_determinant() const { return log_det_; }

 private:
  NoiseModel model_;
  std::vector<Eigen::Index> rows_;
  std::vector<double> decay_;     // per row: the Gauss-Markov decay since the previous row
  std::vector<double> inv_sd_;    // per row: 1 / sqrt(innovation variance)
  std::vector<Eigen::Vector2d> gain_;
  double log_det_ = 0.0;
};

}  // namespace gyrosid
