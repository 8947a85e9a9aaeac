// One gyro of a triad recording seen as a single-gyro recording (`--axis x|y|z`): gyro_<a>_dps, ref_rate_<a>_dps
// and temp_<a>_c (or the triad's one temp_c) under the single-gyro names gyro_dps, ref_rate_dps and temp_c, so
// every single-gyro command (calibrate with a single-gyro model, compensate, allan, explain) meets a triad
// the same way.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/recording.h"

namespace gyrosid {

// The columns that hold one gyro's output, reference rate and temperature.
struct GyroColumns {
  std::string gyro = "gyro_dps", ref = "ref_rate_dps";
  std::string temp;  // empty when the recording has no temperature
  std::string axis;  // x, y or z for a triad's gyro; empty for a single-gyro recording
};

// The gyro a single-gyro command reads from a recording with these columns: a triad needs `axis` (x, y or z),
// a single-gyro recording refuses one. Errors name `source` and the option.
GyroColumns gyro_columns(const std::vector<std::string>& names, const std::string& axis, const std::string& source);

// A triad's other axes' reference rates, named as in the triad (explain's cross-axis channels).
using NamedColumns = std::vector<std::pair<std::string, std::vector<double>>>;

// The recording as a single-gyro recording of gyro `axis`: the gyro's columns renamed (gyro_dps, ref_rate_dps,
// temp_c), the other axes' gyro and temperature columns left out, their reference rates moved to
// `other_references` (when given; else left out), every other column (t_s, accel_*, position_id,
// auxiliaries) kept as it is. A single-gyro recording with an empty axis comes back unchanged.
Recording single_axis_view(Recording recording, const std::string& axis, NamedColumns* other_references = nullptr);

}  // namespace gyrosid
