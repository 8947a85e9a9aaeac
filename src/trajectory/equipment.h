// What the laboratory's hardware can do, in an equipment file (configs/equipment/*.yaml). A design respects
// it; a programme carries its chamber and table limits and TableProfile::check_limits enforces them.
//
//   kind: equipment
//   name: thesis laboratory (du Plessis 2013, s4.4)
//   chamber: {min_c: -70, max_c: 180, heating_c_per_min: 5, cooling_c_per_min: 5}
//   table: {max_rate_dps: 500, max_acceleration_dps2: 100, slip_ring: true}
//
// Units in the key names; every key but `kind` optional (absent: the thesis's chamber, an unlimited table).
// A table without a slip ring cannot turn without limit: such a file is refused until designs can keep the
// table's travel (they use rate cycles with a net rotation).
#pragma once

#include <string>

#include "trajectory/table_profile.h"

namespace gyrosid {

struct Equipment {
  std::string name;
  ChamberLimits chamber;
  TableLimits table;
  double table_max_rate_radps = INFINITY;
};

// Errors name the file, the line and the key.
Equipment load_equipment(const std::string& path);

// The programme as a controller's setpoint table (CSV): at every breakpoint of the chamber ramps and the
// table's rate (segment boundaries, a triangle's low and high vertices) the time, the chamber set point and
// the table rate; linear interpolation between rows reproduces the programme exactly. A jump (a new segment's
// rate) is two rows at the same time.
//   t_s,chamber_setpoint_c,table_rate_dps,position
std::string setpoint_table_csv(const TableProfile& profile);

}  // namespace gyrosid
