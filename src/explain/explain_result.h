// What `gyrosid explain` concludes, as typed results: the verdict, the effects found with their parameters,
// alternatives and held-out evidence, the structure left unexplained and where it sits, the noise, the fit
// before and after, and the record of the selection. Written to and read from explain.json in one place
// (report/explain_json.h).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/enum_names.h"
#include "explain/diagnostics.h"
#include "explain/effect.h"
#include "noise/state_space.h"
#include "explain/selection.h"

namespace gyrosid::explain {

enum class Verdict { missing_physics, unexplained_residual, no_missing_physics };
enum class UnexplainedKind { follows_channel, change_point, trend_change, correlation, time_window, temperature_rate_cell };

}  // namespace gyrosid::explain

namespace gyrosid {
template <>
struct EnumNames<explain::Verdict> {
  static constexpr std::string_view kNoun = "verdict";
  static constexpr std::array<std::pair<explain::Verdict, std::string_view>, 3> kTable{
      {{explain::Verdict::missing_physics, "missing_physics"},
       {explain::Verdict::unexplained_residual, "unexplained_residual"},
       {explain::Verdict::no_missing_physics, "no_missing_physics"}}};
};
template <>
struct EnumNames<explain::UnexplainedKind> {
  static constexpr std::string_view kNoun = "unexplained structure";
  static constexpr std::array<std::pair<explain::UnexplainedKind, std::string_view>, 6> kTable{
      {{explain::UnexplainedKind::follows_channel, "follows_channel"},
       {explain::UnexplainedKind::change_point, "change_point"},
       {explain::UnexplainedKind::trend_change, "trend_change"},
       {explain::UnexplainedKind::correlation, "correlation"},
       {explain::UnexplainedKind::time_window, "time_window"},
       {explain::UnexplainedKind::temperature_rate_cell, "temperature_rate_cell"}}};
};
}  // namespace gyrosid

namespace gyrosid::explain {

struct SeparatingExperiment {
  std::string alternative, experiment;
};

struct FoundEffect {
  std::string id, description;
  std::vector<PhysicalParameter> parameters;  // with 95 % intervals (time constants' asymmetric)
  double delta_bic = 0.0, p_value = 1.0;
  std::vector<std::string> alternatives;         // the recording cannot tell these apart from it
  std::vector<std::string> weaker_alternatives;  // explain much of the same, clearly less well
  std::vector<SeparatingExperiment> separating;  // for each alternative, the experiment that would separate
  double stability = 1.0;                        // fraction of leave-one-block-out refits keeping it
  std::optional<double> heldout_z;               // its held-out gain over its noise; none: the blocks cannot test it
  bool heldout_confirmed() const { return heldout_z && *heldout_z > 2.0; }
  // The held-out rms of the selected model without this effect (its other coefficients refitted), and the
  // share of the held-out excess over the noise floor, (rms_without^2 - rms_with^2) / (rms_without^2 -
  // floor^2), that the effect removes; none when the held-out excess is within 5 % of the floor's variance.
  double heldout_rms_without_dph = 0.0;
  std::optional<double> heldout_excess_removed;
  // When the held-out blocks do not hold it (it lives in part of the record), its predictive z on its own
  // support (explain/support_check.h), in place of heldout_z; none otherwise.
  std::optional<double> support_z;
};

// A named effect the simulation's own flexible structure (its scale-factor surface or polynomial) absorbs:
// against the simulation with a smooth scale factor in its place the effect is strong, against the simulation
// itself it is not - listed as an alternative explanation of part of that structure, not named, with why and,
// where the effect knows it, the experiment that would separate the two.
struct AbsorbedAlternative {
  std::string id;
  std::string absorbed_by;        // the term kind that absorbs it
  double unique_fraction = 0.0;   // share of its whitened signal outside the simulation's span
  double delta_bic_core = 0.0;    // its dBIC against the simulation with the smooth polynomial instead
  double delta_bic_full = 0.0;    // its dBIC against the simulation itself: the evidence of its own
  // BIC(simulation) - BIC(smooth scale factor with it): above 0 it, not the flexibility, is what the data prefer.
  double delta_bic_over_flexibility = 0.0;
  std::string reason;
  std::string separating_experiment;  // empty where the effect does not know one
};

// Structure no effect explains, and where it sits: in time, in (T, omega), or along a channel.
struct Unexplained {
  UnexplainedKind kind = UnexplainedKind::time_window;
  std::optional<std::string> channel;
  double t_start_s = 0.0, t_end_s = 0.0;
  double statistic = 0.0;  // dBIC (follows_channel), peak correlation, or z
  // follows_channel, change_point, trend_change: the selection's p-value and the coefficient (a channel's
  // gain, a step's height, a trend's slope); the change's time is t_start_s = t_end_s, or, where it lies in
  // a held-out run the training rows cannot place it in, that run (from its first row to the next training
  // row, widened to the time found).
  double p_value = 1.0;
  std::vector<PhysicalParameter> parameters;
  // correlation: at which lag, against which threshold.
  double lag_s = 0.0, threshold = 0.0;
  // time_window, temperature_rate_cell: the mean residual there.
  double mean_dph = 0.0;
  // temperature_rate_cell: the cell.
  std::array<double, 2> temp_c{}, rate_dps{};
  bool heating = true;
};

// An effect the selection added but judging demoted, and why (unstable, not confirmed on the held-out
// blocks or on its own support, or weak evidence the held-out blocks cannot test).
struct DemotedEffect {
  std::string id;
  double delta_bic = 0.0, stability = 0.0, heldout_gain_dph2 = 0.0;
  std::optional<double> heldout_z;
  std::optional<double> support_z;  // its predictive z on its own support, when the held-out blocks do not hold it
  std::string reason;
};

struct NoiseSummary {
  std::vector<NoiseTerm> terms;  // IEEE Std 952 terms of the residual after the refit
  NoiseModel whitening;          // the final whitening model
  double floor_dph = 0.0;        // its stationary sigma
};

struct FitSummary {
  double rms_simulation_dph = 0.0, rms_before_dph = 0.0, rms_after_dph = 0.0;  // training samples
  double heldout_rms_before_dph = 0.0, heldout_rms_after_dph = 0.0;
  std::string refit_solver = "ceres", refit_termination;
  int refit_iterations = 0;
  bool refit_covariance = false;
};

struct RecordingSummary {
  std::string source, axis;
  long samples = 0, training_samples = 0;
  double duration_s = 0.0;
  int blocks = 0;
  bool thermal_cycles = false;
  int heldout_every = 4;  // every heldout_every-th block from the third is held out
  long heldout_outside_support = 0;  // held-out samples where the simulation or the refitted model extrapolates (heldout_support.h)
  std::vector<std::string> skipped_channels;
  bool temperature_recorded = true;  // false: no thermometer, the temperature held (no temperature effect testable)
  // Block means the recording was reduced to before explaining (core/decimation.h's to_json, with
  // "statement" and the refitted model's "averaging_bias_dph"); null when it was explained as recorded.
  nlohmann::json decimation;
};

struct SelectionRecord {
  double alpha = 0.05;
  int bootstrap = 0;
  std::uint64_t seed = 0;
  std::vector<std::vector<CandidateScore>> steps;
  std::vector<std::string> untestable;
  NoiseModel whitening;
};

struct ExplainSummary {
  Verdict verdict = Verdict::no_missing_physics;
  std::vector<FoundEffect> effects;
  std::vector<DemotedEffect> demoted;
  std::vector<AbsorbedAlternative> absorbed_alternatives;
  std::vector<Unexplained> unexplained;
  NoiseSummary noise;
  FitSummary fit;
  RecordingSummary recording;
  std::string simulation;  // what the recording was compared with
  SelectionRecord selection;
  Diagnostics before, after;
  double run_time_s = 0.0;
  StageTimes stage_times;  // wall time per stage (selection's parts prefixed "selection: ")
};

}  // namespace gyrosid::explain
