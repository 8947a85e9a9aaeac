// Calibration trajectories from YAML (configs/trajectories/*.yaml): the profile kind and its parameters,
// the chamber's limits, the table's latitude and the sampling. Kind `programme` lists its segments
// explicitly (trajectory/programme.h).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "core/config.h"
#include "core/enum_names.h"
#include "trajectory/table_profile.h"

namespace gyrosid {

enum class CalibrationKind { static_run, thermal_ramp, classical_soak, single_scan, dual_scan, test_cycles, programme };

template <>
struct EnumNames<CalibrationKind> {
  static constexpr std::string_view kNoun = "calibration trajectory kind";
  static constexpr std::array<std::pair<CalibrationKind, std::string_view>, 7> kTable{
      {{CalibrationKind::static_run, "static"},
       {CalibrationKind::thermal_ramp, "thermal_ramp"},
       {CalibrationKind::classical_soak, "classical_soak"},
       {CalibrationKind::single_scan, "single_scan"},
       {CalibrationKind::dual_scan, "dual_scan"},
       {CalibrationKind::test_cycles, "test_cycles"},
       {CalibrationKind::programme, "programme"}}};
};

struct TrajectorySpec {
  TableProfile profile;
  Sampling sampling;
  std::string description;
  std::vector<double> times() const { return sample_times(profile.duration_s(), sampling); }
};

TrajectorySpec load_trajectory(const ConfigNode& node);
TrajectorySpec load_trajectory_file(const std::string& path);

}  // namespace gyrosid
