// Fitting the hybrid model (model/hybrid_model.h) to a recording: the physics terms' columns at the reference
// (true) rate are the flat-prior fixed columns of the evidence problem (bayes_fit.h), the RBF part takes the
// normalised (true rate, temperature), and everything the `bayes` solver does - widths, prior and noise by
// type-II maximum likelihood, coloured noise by Kalman whitening - applies. With nodes = 0 and the true
// model's terms and noise given, its posterior is the Cramer-Rao bound of the true model along the
// recording (the floor the noisy-calibration experiment compares with).
#pragma once

#include <memory>

#include "core/recording.h"
#include "model/hybrid_model.h"
#include "solvers/bayes/bayes_fit.h"

namespace gyrosid {

struct HybridOptions : BayesFitOptions {
  int bias_order = 3;                // bias polynomial in temperature
  int sf_temperature_order = 2;      // scale factor: omega dT^i u^j, i <= this ...
  int sf_rate_order = 3;             // ... and j <= this
  bool asymmetry = false;            // |omega| term
  std::string surface_temperatures_c, surface_rates_dps;  // given: the scale factor as a surface on this grid instead
  OptionTable table();
  std::string validate() const;
  std::vector<Term> terms() const;
};

std::unique_ptr<HybridModel> fit_hybrid(const Recording& recording, const HybridOptions& options, SolveSummary& summary);

}  // namespace gyrosid
