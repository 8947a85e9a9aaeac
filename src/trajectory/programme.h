// The general calibration trajectory: an explicit programme of table-plus-chamber segments (kind
// `programme` in a trajectory YAML). Every hand-made kind (static, ramp, soak, scans, test cycles) is a
// special case; `gyrosid design` writes its designs in this form, and any trajectory can be written out in
// it (`programme_yaml`) and read back to the same profile.
//
//   kind: programme
//   chamber: {rate_limit_c_per_min: 5, min_c: -70, max_c: 180}
//   segments:
//     - {label: plateau, duration_min: 12, chamber_c: [10, 10],
//        rate_dps: {triangle: [-100, 100], cycles: 8, phase: 0.25}, position: 2}
//     - {duration_min: 20, chamber_c: [10, -30], rate_dps: 0}       # a ramp with the table at rest
//   sampling: {rate_hz: 3}
//
// chamber_c is [start, end] (a single number holds); successive segments must join (the chamber cannot
// jump) and every segment keeps the chamber's range and rate limit - checked by TableProfile::check_limits
// exactly as for the hand-made kinds. rate_dps is a constant or a triangle wave low -> high -> low with
// `cycles` full cycles over the segment starting at cycle fraction `phase`.
#pragma once

#include <string>
#include <vector>

#include "core/config.h"
#include "trajectory/table_profile.h"

namespace gyrosid {

struct TrajectorySpec;

// The segments of a programme node (its `segments` list); `default_position` where a segment names none.
std::vector<ProfileSegment> load_programme_segments(const ConfigNode& node, int default_position);

// The trajectory as a programme YAML, every number written to round-trip exactly.
std::string programme_yaml(const TrajectorySpec& spec);

}  // namespace gyrosid
