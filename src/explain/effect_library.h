// The library of named physical effects the missing-physics finder can add to a simulation, each with the
// regressor columns it adds (physics_terms.h) and its nonlinear parameter, and the library of noise terms
// (which are reported, never added as deterministic effects).
//
// Base families - what a simulation already has and may always re-estimate - are term lists too: the
// thesis's unified model (bias cubic in T, scale factor a smooth function of (T, omega)) or the structure of
// a given model. A candidate adds what the base lacks: higher temperature orders, missing rate orders, and
// the named effects below.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "explain/explain_input.h"
#include "model/calibration_model.h"
#include "model/physics_terms.h"

namespace gyrosid::explain {

enum class BaselineForm { surface, polynomial };

enum class EffectId {
  temperature_bias,
  shupe,
  thermal_lag,
  thermal_hysteresis,
  warmup_transient,
  aging_trend,
  scale_factor_asymmetry,
  scale_factor_nonlinearity,
  scale_factor_temperature,
  g_sensitivity,
  g2_sensitivity,
  magnetic_sensitivity,
  cross_axis_coupling,
  auxiliary_channel,  // not physics: a recorded channel the residual follows, reported as unexplained
};

}  // namespace gyrosid::explain

namespace gyrosid {
template <>
struct EnumNames<explain::BaselineForm> {
  static constexpr std::string_view kNoun = "baseline form";
  static constexpr std::array<std::pair<explain::BaselineForm, std::string_view>, 2> kTable{
      {{explain::BaselineForm::surface, "surface"}, {explain::BaselineForm::polynomial, "polynomial"}}};
};

template <>
struct EnumNames<explain::EffectId> {
  using E = explain::EffectId;
  static constexpr std::string_view kNoun = "effect";
  static constexpr std::array<std::pair<E, std::string_view>, 14> kTable{{{E::temperature_bias, "temperature_bias"},
                                                                         {E::shupe, "shupe"},
                                                                         {E::thermal_lag, "thermal_lag"},
                                                                         {E::thermal_hysteresis, "thermal_hysteresis"},
                                                                         {E::warmup_transient, "warmup_transient"},
                                                                         {E::aging_trend, "aging_trend"},
                                                                         {E::scale_factor_asymmetry, "scale_factor_asymmetry"},
                                                                         {E::scale_factor_nonlinearity, "scale_factor_nonlinearity"},
                                                                         {E::scale_factor_temperature, "scale_factor_temperature"},
                                                                         {E::g_sensitivity, "g_sensitivity"},
                                                                         {E::g2_sensitivity, "g2_sensitivity"},
                                                                         {E::magnetic_sensitivity, "magnetic_sensitivity"},
                                                                         {E::cross_axis_coupling, "cross_axis_coupling"},
                                                                         {E::auxiliary_channel, "auxiliary_channel"}}};
};
}  // namespace gyrosid

namespace gyrosid::explain {

// One sentence of physics a navigation engineer would accept.
std::string_view describe(EffectId id);
// The noise terms (Allan-deviation slopes) and their descriptions.
std::string_view describe_noise(std::string_view noise_id);

// What would tell two effects apart when a recording cannot (e.g. Shupe and hysteresis from one ramp rate).
std::string separating_experiment(EffectId a, EffectId b);

// The thesis's unified model as terms: bias, bias in T to order 3, and the scale factor either as a
// bicubic surface on the thesis's (T, omega) grid narrowed to the data's range (surface) or as a polynomial
// omega dT^i u^j, i, j <= 3 (polynomial; also when the data span too little for a grid).
std::vector<Term> baseline_family(BaselineForm form, const Signals& s);
// The terms a given model already has (its coefficients may be re-estimated); its thermal lag in *lag_tau_s.
// Black-box models (RBF) stand for a smooth 2-D error function: the baseline family.
std::vector<Term> structure_of(const CalibrationModel& model, BaselineForm form, const Signals& s, double* lag_tau_s);

enum class NonlinearParameter { none, lag_tau, warmup_tau };

struct Candidate {
  EffectId id = EffectId::temperature_bias;
  Term term;                             // the added columns (thermal_lag: unused, see candidate_columns)
  NonlinearParameter nonlinear = NonlinearParameter::none;
  std::vector<double> tau_grid_s;        // values tried for the nonlinear parameter
};

// The candidates the data can test given the base terms; reasons for untestable ones into `untestable`.
std::vector<Candidate> make_candidates(const std::vector<Term>& base, double base_lag_tau_s, const ExplainInput& in,
                                       std::vector<std::string>* untestable);

// The columns a candidate adds at nonlinear parameter tau. For thermal_lag it is one column: the change of
// the model's prediction (coefficients `beta`, one per design column of `base`) when the coil lags by tau
// instead of base_lag_tau_s - the Gauss-Newton direction of the one-parameter lag model, not a free re-fit
// of every temperature column.
Eigen::MatrixXd candidate_columns(const Candidate& c, double tau_s, const std::vector<Term>& base, double base_lag_tau_s,
                                  const Eigen::VectorXd& beta, const Signals& s, const TermScaling& scaling);

}  // namespace gyrosid::explain
