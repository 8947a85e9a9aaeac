// Detection and ranking of missing effects by forward selection in the whitened space.
//
// The noise model (white + random walk + Gauss-Markov, noise_model.h) is estimated once from the residual of
// the full model - the base plus every candidate - so that structure the base lacks is not taken for noise
// (NoiseModelSource::current re-estimates it from the current model at every step: conservative, blind to
// slow effects). At every step, on the training samples:
//   1. the current model's whitened columns span Q; its whitened residual is r;
//   2. each candidate's whitened columns (at each value of its nonlinear parameter) are projected off Q
//      (what the base can already absorb) and orthonormalised to Z; its statistic is |Z' r|^2, the drop
//      in the residual sum of squares, maximised over the parameter grid;
//   3. its likelihood ratio LR = n log(RSS / (RSS - stat)) and dBIC = LR - (k + q) log n (q nonlinear
//      parameters, a searched change time counted twice: Candidate::bic_parameters);
//   4. its p-value comes from a circular block bootstrap of r - the same maximisation over the parameter
//      grid on every resample, so a lag search is not judged by a plain chi-square;
//   5. Holm's step-down procedure over the candidates controls the family-wise error at alpha;
//   6. the significant candidates are re-scored against the noise the null's likelihood chose (each one's
//      nonlinear parameter scanned again there; a coil lag as the model it creates - the temperature columns
//      lagged, not its Gauss-Newton column beside them), the best `likelihood_tries` of them there - and the
//      best `likelihood_tries` by their dBIC at the step's whitening, where a change the null's noise has
//      absorbed as a random walk still scores - are judged with the noise model (its random-walk and
//      Gauss-Markov variances and time constant) re-estimated by maximum likelihood with and without them - coloured noise can mimic a trend, but a wander is not explained
//      better by one - and the one with the largest positive dBIC there is added; every other candidate within
//      `ambiguity_bic` of it that it makes redundant - and that makes it redundant - is reported as an
//      alternative the data cannot tell apart, by the step's whitened fit or, for the candidates the
//      likelihood tried, by that likelihood with the pair in (its noise maximised again).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/checkpoint.h"
#include "explain/effect.h"
#include "explain/stage_times.h"
#include "noise/state_space.h"

namespace gyrosid::explain {
enum class NoiseModelSource { full, current };
}  // namespace gyrosid::explain

namespace gyrosid {
template <>
struct EnumNames<explain::NoiseModelSource> {
  static constexpr std::string_view kNoun = "noise-model source";
  static constexpr std::array<std::pair<explain::NoiseModelSource, std::string_view>, 2> kTable{
      {{explain::NoiseModelSource::full, "full"}, {explain::NoiseModelSource::current, "current"}}};
};
}  // namespace gyrosid

namespace gyrosid::explain {

// Where the whitening model comes from: the residual of the full model (base plus every candidate) once,
// or the current model's residual at every step (conservative: unexplained structure counts as noise).

struct SelectionOptions {
  double alpha = 0.05;
  int bootstrap = 999;
  int max_effects = 6;
  double ambiguity_bic = 10.0;  // Kass & Raftery: 2 ln BF above 10 is very strong evidence
  // Candidates per step and ranking the likelihood gate maximises the noise for (the best by their dBIC at the
  // null's noise, and by their dBIC at the step's whitening).
  int likelihood_tries = 2;
  std::uint64_t seed = 1;
  NoiseModelSource noise_model = NoiseModelSource::full;
  std::string validate() const;
};

struct CandidateScore {
  std::string id;             // the effect's
  double tau_s = std::numeric_limits<double>::quiet_NaN();  // best nonlinear parameter, if any
  int columns = 0;            // new directions after projecting off the model
  double delta_rss = 0.0;     // whitened
  double lr = 0.0;
  double delta_bic = 0.0;
  double p_value = 1.0;
  bool significant = false;   // after Holm
  // dBIC at the noise the null's likelihood chose, the likelihood gate's ranking (NaN if not gated)
  double held_delta_bic = std::numeric_limits<double>::quiet_NaN();
  // dBIC with the noise re-estimated by maximum likelihood with and without the candidate (NaN if not tried)
  double ml_delta_bic = std::numeric_limits<double>::quiet_NaN();
};

struct SelectedEffect {
  Candidate candidate;
  CandidateScore score;
  std::vector<std::string> alternatives;         // the data cannot tell these apart from it
  std::vector<std::string> weaker_alternatives;  // explain much of the same, but clearly less well
  // Parameters its term gained, besides columns, when a richer form chosen on a grid took its place
  // (take_richer_form).
  int form_parameters = 0;
  int nonlinear_parameters() const { return candidate.nonlinear_parameters() + form_parameters; }
};

struct SelectionResult {
  ModelSpec model;                               // base plus the selected effects
  std::vector<SelectedEffect> effects;
  std::vector<std::vector<CandidateScore>> steps;  // every candidate's score at every step
  NoiseModel noise;                              // the whitening model
  std::size_t whitened_samples = 0;
  int bootstrap = 0;                             // resamples used (raised so Holm's smallest threshold is reachable)
  StageTimes times;                              // wall time per part of the selection
};

// The whitener of the training samples for a noise model.
Whitener training_whitener(const ExplainInput& in, const NoiseModel& noise);
// The columns a candidate adds to a model fitted with coefficients beta (deg/h per column unit).
Eigen::MatrixXd candidate_columns(const Candidate& c, double tau_s, const ModelSpec& model, const Eigen::VectorXd& beta,
                                  const Signals& s, const TermScaling& scaling);

// `y` is the target in deg/h on every sample (the error, minus any fixed offset).
SelectionResult select_effects(const ExplainInput& in, const Eigen::VectorXd& y, const ModelSpec& base,
                               const TermScaling& scaling, const std::vector<Candidate>& candidates,
                               const SelectionOptions& options, Checkpoint* checkpoint = nullptr);

// A candidate tested against two models: the full one, and a core whose flexible structure (a
// scale-factor surface) is replaced by a smooth polynomial. An effect the full model absorbs but the core
// does not is an alternative explanation of part of that structure, with weak evidence of its own.
struct AbsorptionTest {
  double delta_bic_full = 0.0, delta_bic_core = 0.0;
  // BIC(full) - BIC(core with it): above 0, the core with this effect fits better than the full model's
  // flexibility does (that flexibility's own evidence over the core, less this effect's).
  double delta_bic_over_flexibility = 0.0;
  double unique_fraction = 0.0;  // share of its whitened columns' norm outside the full model's span
  double tau_s = 0.0;            // its nonlinear parameter at the core's best
};
// One test per candidate (the two models fitted once).
std::vector<AbsorptionTest> absorption_tests(const std::vector<Candidate>& candidates, const ModelSpec& full, const ModelSpec& core,
                                             const ExplainInput& in, const Eigen::VectorXd& y, const TermScaling& scaling, const Whitener& w);

}  // namespace gyrosid::explain
