// Judging the selected effects before they are accepted: each must keep dBIC > 0 when one training block
// is left out (stability) and, where the held-out blocks see it, improve them significantly - the gain
// |d|^2 + 2 r'd in the whitened held-out residual (d the change the effect makes, r the residual with it)
// against its noise 2 sigma |d|, on the held-out samples where neither model extrapolates (heldout_support.h).
// An effect confined to part of the record that the held-out blocks do not hold is tested by the same gain
// on its own support, in blocked cross-validation (support_check.h).
#pragma once

#include <optional>
#include <vector>

#include "explain/heldout_support.h"
#include "explain/refit.h"
#include "explain/selection.h"
#include "explain/support_check.h"

namespace gyrosid::explain {

// An effect selected after one with several time constants (a warm-up), tested against that effect's further
// component: the selected model without it and with the other's second time constant, the two time constants
// refitted together. A one-exponential warm-up fitted to two leaves the slower one's tail, which an ageing
// trend added later takes (the independent generator's 600 s + 2,400 s warm-up); when the second time
// constant explains the same (dBIC of the effect over it below the ambiguity threshold), the effect is not
// named with confidence but reported as an alternative of the other.
struct FurtherComponent {
  std::string of;          // the effect whose further component it was tested against
  double tau_s = 0.0;      // that component's time constant at the optimum
  double first_tau_s = 0.0;  // the first component's, refitted with it
  double delta_bic = 0.0;  // the effect's dBIC over the model with the further component instead
};

struct Judged {
  SelectedEffect effect;
  std::optional<Term> term;      // the effect's term in the selected model; none for the coil lag
  double stability = 1.0;        // fraction of leave-one-training-block-out refits with dBIC > 0
  double heldout_gain = 0.0;     // held-out sum of squares without the effect minus with it, (deg/h)^2
  double heldout_rss_without = 0.0;  // held-out sum of squares of the selected model without it, (deg/h)^2
  std::size_t heldout_samples = 0;  // the held-out samples scored: inside the support of the baseline and of both models
  double heldout_z = 0.0;        // that gain in the whitened held-out samples over its standard error
  bool heldout_testable = false; // the held-out blocks see the effect (the two predictions differ there)
  // Whether the held-out blocks hold the effect's own signal and, when they do not, its predictive check on
  // its own support (support_check.h): the held-out test above then measures only the refit's side effects.
  bool heldout_holds = true;
  std::optional<SupportCheck> support;
  // Its dBIC against the selected model without it when the others' nonlinear parameters (a lag, a
  // warm-up's tau) are re-optimised without it (a profile likelihood): a lag refitted may explain what a
  // Shupe term took at the lag's old value. None when no other nonlinear parameter is left to refit.
  std::optional<double> profiled_delta_bic;
  // The selected model without it, its nonlinear parameters at that profile's optimum (the refit's start
  // when it is the only effect demoted).
  std::optional<ProfiledFit> profiled_without;
  std::optional<FurtherComponent> further;

  bool rivalled_by_further_component(double ambiguity_bic) const { return further && further->delta_bic < ambiguity_bic; }

  bool explained_by_others() const { return profiled_delta_bic && *profiled_delta_bic <= 0; }
  // The held-out blocks cannot test it and its evidence against the coloured noise re-estimated by maximum
  // likelihood (the selection's gate) is below `untested_bic`: with no confirmation out of sample, in-sample
  // evidence must be very strong - a slow wander the noise model misplaced passes a weak gate.
  // An effect the held-out blocks do not hold needs it too, besides its check on its own support.
  bool weak_and_untested(double untested_bic) const {
    return (!heldout_testable || !heldout_holds) && !(effect.score.ml_delta_bic >= untested_bic);
  }
  // Tested out of sample: on the held-out blocks when they hold it, else on its own support; its z there.
  bool tested() const { return heldout_holds ? heldout_testable : support && support->testable; }
  double tested_z() const { return heldout_holds ? heldout_z : support ? support->z : 0.0; }
  bool accepted(double min_stability, double untested_bic) const {
    return stability >= min_stability && (!tested() || tested_z() > 2.0) && !explained_by_others() && !weak_and_untested(untested_bic) &&
           !rivalled_by_further_component(untested_bic);
  }
};

struct Judgement {
  std::vector<Judged> effects;
  std::optional<ProfiledFit> full;  // the selected model's profile, when a nonlinear parameter was re-optimised
};

// `y` in deg/h on every sample; `w` the training whitener of the selection's noise model; `support` the
// recording's held-out support (each effect is scored held out on the rows inside the support of the
// baseline, the selected model and the selected model without it); `candidates` the selection's (their
// further components are the rivals above); `support_check` how an effect the held-out blocks do not hold
// is checked on its own support.
Judgement judge_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base, const SelectionResult& sel,
                        const TermScaling& scaling, const Whitener& w, HeldoutSupport& support, const std::vector<Candidate>& candidates = {},
                        const SupportCheckOptions& support_check = {});

// Generalised least squares on the rows a whitener covers: coefficients, RSS, count and rank.
struct RowFit {
  Eigen::VectorXd beta;
  double rss = 0.0;
  std::size_t n = 0;
  int rank = 0;
};
RowFit gls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Whitener& w);

}  // namespace gyrosid::explain
