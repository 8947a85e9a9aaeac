// What the missing-physics finder reads from a recording: one gyro's rate error against the reference,
// its inputs as physics-term signals, the recorded channels grouped by meaning, and the split into blocks
// - whole thermal cycles where the recording has them - of which some are held out for confirmation.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/recording.h"
#include "model/physics_terms.h"

namespace gyrosid::explain {

struct InputOptions {
  std::string axis;            // triads: x, y or z; empty for a single-gyro recording
  int heldout_every = 4;       // every n-th block (from the third) is held out
  std::string validate() const;
};

struct ExplainInput {
  std::string source;
  // The physics terms are functions of the true rate: signals.rate is the reference (rad/s); channels hold
  // specific force, magnetic field, the other axes' rates and auxiliaries.
  Signals signals;
  Eigen::VectorXd error;       // gyro output - reference, rad/s
  std::vector<std::string> accel, magnetic, cross_axis, aux;  // channel names by group (no nan in any)
  std::vector<std::string> skipped;                            // channels left out (nan), with the reason
  std::vector<int> block;      // block index per sample
  std::vector<char> heldout;   // 1 for held-out samples
  // Held-out samples the reported held-out fit leaves out: outside the training blocks' support of the
  // baseline's columns or of the refitted model's (heldout_support.h) - the baseline's alone until the
  // refit. Each effect's held-out test uses its own comparison's mask (judge.h). Empty until the simulation
  // is known (explain_recording sets it).
  std::vector<char> outside_support;
  std::vector<int> segment;    // runs of uniform sampling (a gap over 1.5 sample intervals starts a new one)
  int blocks = 0;
  bool thermal_cycles = false; // blocks are whole thermal cycles (else equal time blocks)
  double dt_s = 1.0;           // median sample interval
  bool temperature_recorded = true;  // false: no temperature column; signals.temp_c is then held at 0 C

  Eigen::Index size() const { return error.size(); }
  Eigen::Index training_size() const;
  // A held-out sample that confirms: held out and inside the training blocks' support (of `outside`, a
  // mask of HeldoutSupport; by default outside_support).
  bool confirms(Eigen::Index i, const std::vector<char>& outside) const {
    const auto k = static_cast<std::size_t>(i);
    return heldout[k] != 0 && (outside.empty() || outside[k] == 0);
  }
  bool confirms(Eigen::Index i) const { return confirms(i, outside_support); }
  // A sample the residual diagnostics see: a training sample. Held out, the residual is a prediction error
  // with the simulation's own parameter error in it - shared by every sample of a (T, omega) cell the
  // training blocks visited sparsely, so a cell or window test there would read extrapolation as structure;
  // the held-out blocks speak through the held-out gain of each effect instead.
  bool diagnosed(Eigen::Index i) const { return heldout[static_cast<std::size_t>(i)] == 0; }
  // The run of held-out rows (first, last) a change at t_s may lie anywhere in for all the training rows
  // say: the run holding a row within ten rows of t_s. None when the training rows place t_s (no held-out
  // row that near).
  std::optional<std::pair<Eigen::Index, Eigen::Index>> heldout_run_at(double t_s) const;
};

// Reads one gyro of a recording. Errors name the recording and the column.
ExplainInput load_input(const Recording& recording, const InputOptions& options);

}  // namespace gyrosid::explain
