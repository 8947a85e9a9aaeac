// An effect the missing-physics finder can add to a simulation, as one self-describing object: its name and
// physics, the candidate it adds to a given model on a given recording (or why the recording cannot test
// it), the candidate's regressor columns, its physical parameters with units from the fitted coefficients,
// and the experiment that tells it apart from another effect. Its C export is its term's (physics_terms.h).
//
// The library (effect_library()) holds one of every registered effect; a new effect is one class (effects/)
// and one entry in effect_registry() (effects/registry.cpp), or from outside the library one line with
// extend_effect_registry(). Effects that are not physics (a recorded
// channel the residual follows, a change point) are selected the same way and reported as unexplained.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/registry.h"
#include "explain/explain_input.h"
#include "model/physics_terms.h"

namespace gyrosid::explain {

class Effect;

// A nonlinear parameter a candidate is tried at (a grid, refined when it is selected and in the refit): the
// coil's thermal lag (which acts on the model's own temperature terms) or the parameter inside the
// candidate's term (a time constant, a transition width, a change point's time).
enum class NonlinearParameter { none, coil_lag, term_parameter };

struct Candidate {
  const Effect* effect = nullptr;
  std::optional<Term> term;          // the columns it adds; none for the coil lag
  NonlinearParameter nonlinear = NonlinearParameter::none;
  std::vector<double> tau_grid_s;    // values tried for the nonlinear parameter
  // A further component of an effect with several time constants (a warm-up's second exponential): not
  // selected on its own, but the rival of an effect selected after the first component (judge.h).
  bool further_component = false;
  // A flexible form (the bias spline in T, ageing that slows), left out of the model whose residual sets the
  // selection's whitening (selection.cpp, full_model_noise): there it takes part of every other effect of its
  // input, or of the noise, and moves the noise model they are judged by (third generator, seed 31106: a
  // 0.5-sigma hysteresis then won a wrong Shupe partner and both were demoted held out).
  bool flexible_form = false;
  std::string_view id() const;
  int nonlinear_parameters() const { return nonlinear == NonlinearParameter::none ? 0 : 1; }
  // Its count in a BIC penalty beside its columns: a location searched over the record (a change point's
  // time) is not a regular parameter and counts twice - the modified BIC of Zhang & Siegmund (2007,
  // Biometrics 63:22), 3/2 ln n of log-likelihood per change, i.e. 3 ln n on the 2 log L scale for a step's
  // height and time, where the plain BIC counts 2 ln n. (Its O(1) term in the segment lengths is left out.)
  int bic_parameters() const { return nonlinear_parameters() + (nonlinear == NonlinearParameter::term_parameter && !scale_parameter() ? 1 : 0); }
  // The parameter is a positive scale (refined on a log scale) rather than a location (a time).
  bool scale_parameter() const { return nonlinear != NonlinearParameter::term_parameter || term->parameter()->scale; }
};

// The model a recording is explained against and the recording's ranges, as the effects see them.
struct CandidateContext {
  CandidateContext(const std::vector<Term>& base, double base_lag_tau_s, const ExplainInput& in);

  const std::vector<Term>& base;
  double base_lag_tau_s;
  const ExplainInput& in;
  double duration_s = 0.0;
  bool temp_varies = false;  // the probe temperature spans more than 1 C
  bool rate_varies = false;  // the rate spans more than 1 deg/s
  std::set<int> bias_orders;                // of the base's bias polynomials
  std::set<std::pair<int, int>> sf_orders;  // of the base's scale-factor polynomials

  template <typename T>
  bool base_has() const {
    for (const auto& t : base) {
      if (t.as<T>()) return true;
    }
    return false;
  }
  // Those of `names` that vary by more than `scale` and are not already a (plain) channel term of the base.
  std::vector<std::string> new_varying_channels(const std::vector<std::string>& names, double scale) const;
};

// An effect's candidates on a recording, or why it cannot be tested there (no candidate and no reason:
// nothing to add, e.g. the base already has it).
struct Proposal {
  std::vector<Candidate> candidates;
  std::string untestable;
};

// A physical parameter of a found effect; the name carries its unit (k_dph_per_cpm). Reference values of
// the parametrisation (t_ref_c) carry no interval.
struct PhysicalParameter {
  std::string name;
  double value = 0.0;
  double low = 0.0, high = 0.0;  // 95 % interval
  bool reference = false;
  static PhysicalParameter estimate(std::string name, double value, double sd) {
    return {std::move(name), value, value - 1.96 * sd, value + 1.96 * sd, false};
  }
  static PhysicalParameter reference_value(std::string name, double value) { return {std::move(name), value, value, value, true}; }
};

// The model a candidate's columns are computed against: its terms, lag, coefficients (deg/h per column unit).
struct ModelColumns {
  const std::vector<Term>& terms;
  double lag_tau_s;
  const Eigen::VectorXd& beta;
  const Signals& signals;
  const TermScaling& scaling;
};

class Effect {
 public:
  virtual ~Effect() = default;

  virtual std::string_view id() const = 0;
  // One sentence of physics a navigation engineer would accept.
  virtual std::string_view description() const = 0;
  // Its parameters and their units, for --help.
  virtual std::string_view parameters_help() const = 0;
  // Physics is reported as a found effect; anything else as unexplained structure of this kind
  // (follows_channel, change_point, trend_change).
  virtual bool is_physics() const { return true; }
  virtual std::string_view unexplained_kind() const { return "follows_channel"; }

  virtual Proposal propose(const CandidateContext& context) const = 0;
  // The columns a candidate adds at nonlinear parameter tau: its term, its time constant set to tau.
  virtual Eigen::MatrixXd columns(const Candidate& c, double tau_s, const ModelColumns& model) const;
  // Its physical parameters from its columns' coefficients and standard deviations (deg/h per column unit).
  virtual std::vector<PhysicalParameter> parameters(const Term& term, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                                    const TermScaling& scaling) const;
  // What would tell it apart from `other`, where this effect knows (each pair is written by one of the two).
  virtual std::string separating_experiment(std::string_view other) const;
  // Values of its nonlinear parameter a scan of the base model's residual points at, without a noise model
  // (added to its grid; none by default). The training rows only: a held-out row never fits.
  virtual std::vector<double> located_parameters(const ExplainInput&, const Eigen::VectorXd& residual) const;
  // Richer forms of its term once it is selected (a hysteresis loop of two widths for one, a step with its
  // recovery): each tried in the term's place at the step that selects it, kept when the BIC prefers it with
  // its added columns counted, and one added parameter when it was chosen among several (selection.cpp,
  // take_richer_form). None by default.
  virtual std::vector<Term> richer_forms(const Term& accepted, const ExplainInput& in) const;
  // Where the simulation's flexible scale factor may absorb it, it is tested against a core with a smooth
  // scale factor omega dT^i u^j, i <= 3, j <= this order, in place of that flexibility (explain.cpp,
  // absorbed_alternatives). 3 by default; lower for an effect a cubic in the rate would itself absorb.
  virtual int core_rate_order() const { return 3; }

 protected:
  Candidate candidate(Term term) const;
};

using EffectRegistry = Registry<Effect>;
const EffectRegistry& effect_registry();
// The same registry, open for a program to add its own effects at start-up, before anything reads the
// library (which is built once, from the registry, on first use; not thread-safe). Every added effect is
// tried by every explain run of that program. tests/explain/toy_effect.cpp adds one this way.
EffectRegistry& extend_effect_registry();
// One instance of every registered effect, in registry order (the order candidates are tried in).
const std::vector<const Effect*>& effect_library();
const Effect& find_effect(std::string_view id);  // Error listing the known ids
// The experiment that separates two effects (either may know it), else the generic advice.
std::string separating_experiment(const Effect& a, const Effect& b);

// A model with a candidate added at parameter tau (the coil lag is set; other candidates add their term).
struct ModelSpec {
  std::vector<Term> terms;
  double lag_tau_s = 0.0;
};
ModelSpec with_effect(const ModelSpec& model, const Candidate& c, double tau_s);
// The model's columns along the signals (its coil lag applied).
Eigen::MatrixXd model_columns(const ModelSpec& m, const Signals& s, const TermScaling& scaling);

// n values spaced evenly in log from lo to hi ({lo} when hi <= lo): the grids of nonlinear parameters.
std::vector<double> log_grid(double lo, double hi, int n);

}  // namespace gyrosid::explain
