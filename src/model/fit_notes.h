// What a calibration fit says beside its model, as typed fields: its size, the physics its recording could
// not determine, a lot prior's share and predictive sigma, the noise model it chose.
//
// A fit writes them into its SolveSummary's `details` (the log every model file and report carries) with
// write_fit_notes; code that acts on them - the CLI's notes, the main job's report - reads them back with
// fit_notes_of. The keys live in fit_notes.cpp only.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gyrosid {

// Columns a fit left out because the recording held their input (model/held_inputs.h), and why.
struct PhysicsLeftOut {
  std::vector<std::string> columns;
  std::string note;
};

// The sd of a posterior model's estimated error over the surface grid's nodes (greybox under a lot prior).
struct PredictiveSigma {
  double rms_dph = 0.0, max_dph = 0.0;
  double max_at_temp_c = 0.0, max_at_rate_dps = 0.0;  // the node where it is largest
};

struct FitNotes {
  std::optional<int> nodes;       // RBF and hybrid fits: centres of the network
  std::optional<int> parameters;  // classical and grey-box fits: coefficients (the grey-box lag counted)
  std::optional<PhysicsLeftOut> physics_left_out;
  // Under a lot prior: per term group, the share of its information from the recording (1) or the prior (0).
  std::vector<std::pair<std::string, double>> data_share;
  std::optional<PredictiveSigma> predictive_sigma;
  std::string physics_note;          // grey-box: the ridge, not the recording, set the held inputs' terms
  std::string noise_choice;          // Bayesian fits: what was decided about the noise, and why
  std::string noise_identification;  // Bayesian fits: the residual's noise terms, as `gyrosid allan` gives them
  std::optional<double> ridge_lambda;  // the OLS solver: the global ridge it chose (unit-RMS target); the triad's
                                       // joint rows carry it over (solvers/triad/triad_fit.cpp)

  // "N nodes" or "N coefficients"; "" for a fit that says neither.
  std::string size() const;
};

// Adds the notes that are set to `details`, beside whatever else the fit logs there.
void write_fit_notes(const FitNotes& notes, nlohmann::json& details);
// The notes in a summary's details (a model file's included); absent ones stay unset.
FitNotes fit_notes_of(const nlohmann::json& details);

}  // namespace gyrosid
