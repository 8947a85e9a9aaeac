// The calibration trajectories of the thesis (s4.4) as table profiles. Durations follow from the chamber
// rate: one scan over dT at r C/min takes dT / r minutes (-60..80 C at 5 C/min: 28 min).
//
//   static          constant temperature and table rate (noise characterisation, Allan runs)
//   thermal_ramp    hold, one ramp at the scan rate, hold (the classical "thermal ramp test")
//   classical_soak  plateaus with settling time; at each plateau every mount position of Table 2.1 with a
//                   sequence of table-rate steps (thesis fig 2.2: about 8 h)
//   single_scan     one temperature scan with triangle rate cycling, plus a boundary rate scan at constant
//                   temperature at each end (figs 4.5-4.7)
//   dual_scan       up scan, boundary scan, down scan with the rate cycles out of phase (fig 4.8-4.10: the
//                   "56 min" trajectory counts the two ramps)
//   test_cycles     n temperature cycles (up + down) with m rate cycles per temperature cycle, each cycle's
//                   rate phase shifted so that successive cycles fill each other's gaps (figs 4.13-4.16)
#pragma once

#include <string>
#include <vector>

#include "trajectory/table_profile.h"

namespace gyrosid {

struct StaticOptions {
  double temp_c = 25.0;
  double duration_s = 3600.0;
  double rate_radps = 0.0;
  int position = 2;
  std::string validate() const;
};

struct RampOptions {
  double temp_start_c = -60.0, temp_end_c = 80.0;
  double rate_c_per_min = 5.0;
  double hold_start_min = 0.0, hold_end_min = 0.0;
  double table_rate_radps = 0.0;
  int position = 2;
  std::string validate() const;
};

struct SoakOptions {
  std::vector<double> plateaus_c{-60, -40, -20, 0, 20, 40, 60, 80};
  double ramp_rate_c_per_min = 5.0;
  double settle_min = 30.0;
  std::vector<int> positions{1, 2, 3, 4, 5, 6};
  std::vector<double> rates_radps;  // table-rate steps in every position (include 0 for a static dwell)
  double step_dwell_s = 20.0;
  std::string validate() const;
};

struct ScanOptions {
  double temp_low_c = -60.0, temp_high_c = 80.0;
  double scan_rate_c_per_min = 5.0;
  double rate_low_radps = 0.0, rate_high_radps = 0.0;
  double rate_cycles_per_scan = 16.0;  // full low->high->low rate cycles during one temperature scan
  double boundary_scan_min = 2.0;      // one rate cycle at constant temperature at each scan end (0: none)
  bool start_low = true;               // single scan: upward from temp_low_c, else downward
  int temperature_cycles = 1;          // test_cycles: n
  int position = 2;
  std::string validate() const;
};

TableProfile static_profile(const StaticOptions& options);
TableProfile thermal_ramp(const RampOptions& options);
TableProfile classical_soak(const SoakOptions& options);
TableProfile single_scan(const ScanOptions& options);
TableProfile dual_scan(const ScanOptions& options);
TableProfile test_cycles(const ScanOptions& options);

}  // namespace gyrosid
