// An effect tested where it lives (issue 34, class 3). The held-out blocks are fixed (every n-th block from
// the third, explain_input.h); an effect confined to part of the record - a warm-up transient at the start
// of a run, an onset after the last held-out block - has no signal there, and what the held-out test then
// measures is the side effect of refitting the other terms without it (a z near 0 however strong the
// effect). Such an effect is tested by a predictive check on its own support instead.
//
// The effect's contribution c = X_e beta_e (its columns times its coefficients in the selected model's fit,
// deg/h) locates it. The held-out blocks hold it when their share of its signal, sum c^2 over the confirming
// held-out rows over sum c^2 over every row, is at least `held_share` times their share of the rows;
// otherwise its support is the training samples where |c| >= `material` max |c|, split in time order into
// `folds` contiguous folds. Each fold is predicted by the selected model and by the model without the
// effect, both fitted (generalised least squares under the selection's noise model) on every other training
// sample; the fold's residuals are whitened by the same noise model over the fold alone, and the gains
// add up to one z as in the held-out test: z = sum(|d|^2 + 2 r'd) / (2 sigma_h sqrt(sum |d|^2)), r the
// whitened residual with the effect, d the change without it, sigma_h the rms of r (Arlot & Celisse 2010,
// A survey of cross-validation procedures for model selection: blocked folds for dependent data). The
// effect's nonlinear parameter (a time constant) stays at the selection's value, chosen on every training
// sample - the folds included.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "explain/explain_input.h"
#include "noise/state_space.h"

namespace gyrosid::explain {

struct SupportCheckOptions {
  double held_share = 0.1;   // the held-out blocks hold an effect with at least this fraction of their fair share of its signal
  double material = 0.1;     // its support: |c| at least this fraction of its largest |c|
  int folds = 4;
  int min_fold_samples = 10; // a support of fewer than folds * this training samples is not checked
  std::string validate() const;
};

// The held-out gain of a model over the same model without one effect, accumulated over whitened pieces:
// r the whitened residual with the effect, d = (residual without) - (residual with), whitened.
struct WhitenedGain {
  double dd = 0.0, rd = 0.0, rr = 0.0;
  std::size_t n = 0;
  void add(const Eigen::VectorXd& r, const Eigen::VectorXd& d);
  // The two predictions differ by more than 0.05 of the training noise `sigma` (rms, whitened units).
  bool testable(double sigma) const;
  // (|d|^2 + 2 r'd) / (2 sigma_h |d|), sigma_h the rms of r; 0 when d is 0.
  double z() const;
};

// True when the confirming held-out rows (ExplainInput::confirms with `outside`) hold the effect's
// contribution `c` (every sample, deg/h) by the share rule above; true too when c is zero.
bool heldout_blocks_hold(const ExplainInput& in, const std::vector<char>& outside, const Eigen::VectorXd& c, double held_share);

struct SupportCheck {
  std::size_t samples = 0;          // training samples of the support
  double t_start_s = 0.0, t_end_s = 0.0;  // its first and last
  bool testable = false;            // the two models' predictions differ there (WhitenedGain::testable)
  double z = 0.0;
};

// The predictive check of the effect whose contribution is `c` on its support: `y` (deg/h, every sample),
// the selected model's columns `x_full` and those without the effect `x_minus`, `sigma` the training fit's
// noise level in whitened units. None when the support is too small to fold.
std::optional<SupportCheck> support_check(const ExplainInput& in, const Eigen::VectorXd& y, const NoiseModel& noise, const Eigen::MatrixXd& x_full,
                                          const Eigen::MatrixXd& x_minus, const Eigen::VectorXd& c, double sigma, const SupportCheckOptions& options);

}  // namespace gyrosid::explain
