// The built-in configs (core/config.h's builtin: paths) that commands, jobs and bindings start from by default.
#pragma once

namespace gyrosid {

inline constexpr const char* kDefaultSensor = "builtin:sensors/open_loop_fog.yaml";
inline constexpr const char* kDefaultTrajectory = "builtin:trajectories/dual_scan.yaml";
inline constexpr const char* kStaticTrajectory = "builtin:trajectories/static_2h.yaml";

}  // namespace gyrosid
