// Holds checked for stillness (reference=gravity: the IMU-TK / Tedaldi procedure, holds position_id 1..n, hand
// turns position_id 0, gravity_turns.h). The procedure assumes the body still in every hold: its samples are rows
// against a true rate of zero (they fix the biases), and its mean specific force is where gravity points before
// and after each turn. A hand that keeps moving in a hold breaks both - the fit then shows a large residual but
// not why. This check names such holds.
//
// Statistic: per hold h and axis i, the gyro's sample standard deviation about the hold's mean, s_hi. The noise
// floor of axis i is the quietest hold's, f_i = min_h s_hi (every hold of a session sees the same sensor noise).
// A hold is not still when s_hi > ratio_limit * f_i on some axis (default 3): for white noise the sample
// deviation of n samples scatters by about 1/sqrt(2n) relative (7 % at n = 100), so a factor of 3 is motion, not
// chance. Holds of fewer than 10 samples are not judged (their deviation says little), nor deviations below
// 1e-6 deg/s (far below any real gyro's noise: exact synthetic outputs differ there by rounding only). The check
// is relative: a session whose every hold moves alike has no still reference, and nothing is named.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/triad_model.h"

namespace gyrosid {

struct HoldStillness {
  int position_id = 0;
  double t_start_s = 0.0, t_end_s = 0.0;  // first and last sample
  std::size_t samples = 0;
  std::array<double, 3> gyro_std_dps{};
  double ratio = 0.0;  // max_i s_hi / f_i
  bool still = true;
};

struct HoldStillnessCheck {
  std::vector<HoldStillness> holds;     // every hold, in time order
  std::array<double, 3> floor_dps{};    // f_i
  int quietest_position_id = 0;         // the hold with the lowest rms deviation over the three axes
  double ratio_limit = 3.0;
  std::vector<HoldStillness> not_still() const;
  // "hold position_id 4 (54.35 s to 57.38 s) is not still: gyro std 0.33/2.1/0.5 deg/s, 18x the quietest hold's ..."
  std::string describe(const HoldStillness& h) const;
  nlohmann::json json() const;
};

inline constexpr std::size_t kMinHoldSamples = 10;
inline constexpr double kStillnessResolutionDps = 1e-6;

// The holds are the runs of one non-zero position_id (gravity_turns.h's layout).
HoldStillnessCheck check_hold_stillness(const TriadData& data, double ratio_limit = 3.0);

}  // namespace gyrosid
