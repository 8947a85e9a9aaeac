// Type-II maximum likelihood of a Gaussian RBF network plus flat-prior fixed columns (evidence.h): the
// per-input widths shared by every node by NLopt (gradient-based, analytic gradient; a coarse scan of one
// common width first, and of two inputs' widths on a grid where every common width leaves the network off),
// the prior precision alpha and the noise precision beta by MacKay's fixed point inside every evaluation.
// Centres come from a candidate dictionary: a farthest-point subset of the training inputs
// (solvers/common/candidates.h).
//
// Noise: white, or coloured - white + rate random walk + Gauss-Markov (noise/state_space.h) fitted by Allan
// deviation to the residual of the white fit, the problem whitened by its Kalman filter (generalised least
// squares without an N x N covariance, thesis s5.5.3's open problem), and refitted; the noise model is
// re-estimated from each new residual (`noise_passes`) by the evidence, the random walk kept only where it
// beats a Gauss-Markov wander alone by BIC's penalty for its parameter (within a record the two look alike,
// and a walk discards the level the bias needs). `auto` keeps the coloured fit when its evidence beats
// the white fit's by more than BIC's penalty for the extra noise parameters. A given noise model (known
// noise: the Cramer-Rao floor) fixes beta = 1.
//
// Shared by the `bayes` RBF solver (fixed column: the constant) and the hybrid model (fixed columns: the
// grey-box physics terms).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "core/solve_summary.h"
#include "noise/state_space.h"
#include "solvers/bayes/evidence.h"
#include "solvers/common/options.h"

namespace gyrosid {

struct BayesFitOptions {
  int nodes = 200;                 // dictionary size (0: no RBF part, the fixed columns alone)
  double width = 0.3, min_width = 0.02, max_width = 4.0;  // normalised input units
  bool per_input_widths = true;
  int scan = 6;                    // common widths tried, log-spaced over [scan_min, scan_max], before the search
  double scan_min = 0.06, scan_max = 1.0;
  int evaluations = 30;            // evidence evaluations of each gradient search
  std::string algorithm = "LD_LBFGS";
  std::string noise = "auto";      // auto | white | coloured | given
  int noise_passes = 2;            // coloured: noise-model estimates, each from the previous fit's residual
  // coloured: how the fits along the slow drift term's ridge of equal evidence enter (average_slow_drift):
  // sigma - the covariance only (the mean stays the fit's), mixture - mean and covariance, none
  std::string drift_averaging = "mixture";
  std::string model_error = "cv";  // cv: add the misfit variance cross-validation reveals to the predictive sigma (model_error.h); none
  int model_error_blocks = 10;     // cv: time blocks (folds) when no input is recorded at levels
  std::string model_error_groups = "runs";  // cv: a fold's samples averaged over cells of the input grid or runs in time
  // noise = given: the recording's noise is known (e.g. from `gyrosid allan`, or the truth of a simulation
  // for the Cramer-Rao floor): white (deg/h at 1 Hz), rate random walk (deg/h/rt(h)), Gauss-Markov.
  double given_white_dph_at_1hz = 0.0, given_rrw_dph_rt_h = 0.0, given_gm_sigma_dph = 0.0, given_gm_tau_s = 0.0;
  // Adds the options to a table (shared by the bayes solver and the hybrid fitter).
  void bind(OptionTable& table);
  std::string validate() const;
};

// A problem in normalised inputs: target y (unit RMS), fixed columns f (N x P, flat prior).
struct BayesProblem {
  Eigen::MatrixXd x;           // N x d normalised inputs
  Eigen::VectorXd y;           // N
  Eigen::MatrixXd fixed;       // N x P
  std::vector<double> t_s;     // sample times (empty: unit spacing)
  std::optional<NoiseModel> given_noise;  // known noise model (variances in y units): no estimation, beta = 1
  double report_scale = 1.0;   // y units -> deg/h, for the noise figures in noise_choice
};

struct BayesFit {
  Eigen::MatrixXd centres;     // M x d
  Eigen::RowVectorXd widths;   // d, shared by every node
  Eigen::VectorXd rbf_weights; // M
  Eigen::VectorXd fixed_weights;  // P
  Eigen::MatrixXd covariance;  // (M + P) x (M + P), order [rbf, fixed], y units^2
  double log_alpha = 0.0, log_beta = 0.0, gamma = 0.0, log_evidence = 0.0;
  double noise_sigma = 0.0;    // per-sample white noise sigma, y units
  std::optional<NoiseModel> noise;  // the coloured model trained under (variances in y units, beta applied)
  std::string noise_choice;    // what was decided about the noise, and why
  std::string noise_identification;  // the one noise estimator's reading of the white fit's residual, deg/h
  std::string noise_averaging; // coloured: the weights of the slow term's scales the posterior averages over
  std::string noise_family;    // coloured: whether the random walk was kept over a Gauss-Markov wander alone, and why
  double model_error_var = 0.0;  // misfit variance added to the predictive variance (y units^2; model_error.h)
  std::string model_error_note;  // how it was estimated
  double model_error_excess = 0.0, model_error_standard_error = 0.0, model_error_reach = 1.0;  // the estimate's figures (y units^2)
  double cv_mse = 0.0;  // model_error=cv: the folds' mean squared prediction residual (ModelErrorEstimate), y units^2
  Termination termination = Termination::converged;
  std::string message;
  int evaluations = 0;
  nlohmann::json details(double y_scale) const;  // figures for the solve summary (noise in y_scale units)
};

BayesFit fit_bayes(const BayesProblem& problem, const BayesFitOptions& options, SolveMonitor& monitor);

// The log evidence at given widths (shared by every node) with (alpha, beta) at their optimum from `warm`
// (beta = 1 when fixed_beta: a known noise model), and its gradient with respect to the log widths when
// `gradient` is not null - one evaluation of the width search.
struct EvidenceAt {
  double value;
  Precisions precisions;
};
EvidenceAt evidence_at(const BayesProblem& problem, const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths,
                       const FixedPart& fixed, bool fixed_beta, Precisions warm, Eigen::VectorXd* gradient);

// An input recorded at discrete levels: its sorted values split wherever they jump by over 0.01 (normalised
// units), the jumps covering over half its range. level: every sample's level index (ascending values),
// spacing: the median jump, count: the number of levels; level is empty for a continuous input.
struct InputLevels {
  std::vector<int> level;
  double spacing = 0.0;
  int count = 0;
};
InputLevels input_levels(const Eigen::VectorXd& v);

// The lower bound of each input's width (normalised units): min_width, or for an input recorded at
// discrete levels (gaps over 0.01 covering over half its range) the median spacing of its levels.
std::vector<double> identifiable_min_widths(const Eigen::MatrixXd& x, double min_width);

// The noise model (variances) scaled by `factor`^2 (e.g. from unit-RMS target units to deg/h).
NoiseModel scaled(NoiseModel model, double factor);
// The given noise (options noise=given) for sampling interval dt_s, in units of y_scale rad/s.
NoiseModel given_noise_model(const BayesFitOptions& options, double dt_s, double y_scale);

}  // namespace gyrosid
