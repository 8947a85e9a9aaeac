// Inputs a training recording does not vary. A rate table run at one chamber temperature determines no
// temperature dependence, a thermal soak at rest no scale factor: the fits (classical, hybrid) leave those
// terms out and say so, instead of failing on a rank-deficient design or - worse - fitting the scale factor
// to the noise in the measured rate, which is all a recording at rest has in its rate input.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace gyrosid {

// Spans below which an input counts as held: the spans TermScaling::of already treats as no range.
inline constexpr double kHeldTemperatureSpanC = 1.0;
inline constexpr double kHeldRateSpanDps = 1.0;

struct HeldInputs {
  bool temperature = false, rate = false;
  double temp_span_c = 0.0, temp_mean_c = 0.0;
  double rate_span_dps = 0.0, rate_mean_dps = 0.0;

  // "the temperature stays within 0 C of 25 C" (and / or the rate); empty when nothing is held.
  std::string held() const;
  // For a fit that leaves columns out: "<held>: the recording does not determine dT^1, dT^2 - left out of
  // the physics; the calibration holds at this temperature only".
  std::string left_out_note(const std::vector<std::string>& left_out) const;
  // For a fit that keeps every column (the grey-box model's ridge sets the undetermined ones toward 0):
  // "<held>: the ridge, not the recording, sets the terms in it; ...".
  std::string ridge_note() const;
};

// From the true (reference) rate, rad/s, and the temperature, C, of a recording.
HeldInputs held_inputs(const Eigen::VectorXd& rate_radps, const Eigen::VectorXd& temp_c);

}  // namespace gyrosid
