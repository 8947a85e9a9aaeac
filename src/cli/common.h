// Defaults shared by the subcommands: the built-in configs they start from.
#pragma once

namespace gyrosid::cli {

inline constexpr const char* kDefaultSensor = "builtin:sensors/open_loop_fog.yaml";
inline constexpr const char* kDefaultTrajectory = "builtin:trajectories/dual_scan.yaml";
inline constexpr const char* kStaticTrajectory = "builtin:trajectories/static_2h.yaml";

}  // namespace gyrosid::cli
