// The decision variables of a calibration design: a programme of K table-plus-chamber segments
// (trajectory/programme.h) that fits a time budget, within the chamber's range and rate limit, with the
// table's rate bounded.
//
// Segment i holds a chamber ramp (or plateau) from the previous segment's end temperature towards a target,
// and a rate programme: a triangle wave between two rates (equal rates: a dwell) with a cycle period and a
// starting phase, in one of the allowed mount positions. Two encodings share it:
//
//   box (NLopt):  v = [T_0, per segment: share, target T, rate a, rate b, log10 period, phase (, position)]
//                 in a box. Every v decodes to a feasible programme: durations are the shares of the
//                 budget, the chamber moves towards its target no faster than the limit allows (it stops
//                 short when the segment is too short), low/high = min/max(a, b), cycles = duration / period.
//   smooth (Ipopt): x = [T_0, per segment: duration, end T, rate low, rate high] with the limits as
//                 constraints: sum duration = budget, |T_i - T_{i-1}| <= r duration_i, low <= high; the rate
//                 cycling is relaxed to its occupancy (uniform over [low, high], see observations.h), and a
//                 solution is rounded to cycles of the preferred period with alternating phases.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "trajectory/equipment.h"
#include "trajectory/table_profile.h"
#include "solvers/common/options.h"

namespace gyrosid::design {

struct DesignSpaceOptions {
  double budget_min = 60.0;
  int segments = 6;
  double temp_min_c = NAN, temp_max_c = NAN;  // chamber programme bounds (NaN: the domain +- margin)
  double temperature_margin_c = 10.0;         // chamber bounds beyond the domain (the coil lags the chamber)
  double max_rate_dps = NAN;                  // table rate bound (NaN: the domain's)
  double min_period_s = 40.0, max_period_s = 600.0;  // rate cycle period
  double preferred_period_s = 90.0;           // cycles of a rounded smooth solution
  double min_share = 0.02;                    // smallest segment, fraction of the budget
  double rate_hz = 3.0;                       // sampling of the designed trajectory
  std::vector<int> positions{2};              // mount positions the design may use (Table 2.1)
  double start_c = NAN;                       // the chamber's temperature at the start (NaN: the design chooses;
                                              // an adaptive session's next segment starts where the last ended)
  ChamberLimits chamber;
  double table_max_acceleration_dps2 = NAN;   // NaN: no limit (a triangle's cycles are cut to respect one)
  double table_max_rate_dps = NAN;            // NaN: no limit; else it caps max_rate_dps and the domain's rate
  double latitude_deg = -25.86;
  void bind(OptionTable& table);  // keys space.<name>
  std::string validate() const;
  void take(const Equipment& equipment);  // the chamber's limits and the table's (trajectory/equipment.h)
};

// The smooth encoding's variables in natural units.
struct SmoothProgramme {
  double start_c = 0.0;
  std::vector<double> duration_s, end_c, low_radps, high_radps;
};

class DesignSpace {
 public:
  // `temp_lo/hi`: the domain's temperature range; `rate_max_radps`: the domain's rate range.
  DesignSpace(DesignSpaceOptions options, double domain_temp_lo_c, double domain_temp_hi_c, double domain_rate_max_radps);

  const DesignSpaceOptions& options() const { return o_; }
  double budget_s() const { return o_.budget_min * 60.0; }
  double temp_lo() const { return t_lo_; }
  double temp_hi() const { return t_hi_; }
  double rate_max_radps() const { return w_max_; }

  // Box encoding.
  int box_dimension() const;
  Eigen::VectorXd box_lower() const;
  Eigen::VectorXd box_upper() const;
  TableProfile decode_box(const Eigen::VectorXd& v) const;
  // A programme's box coordinates (the inverse of decode_box for programmes it produced).
  Eigen::VectorXd encode_box(const TableProfile& profile) const;

  // Smooth encoding.
  TableProfile decode_smooth(const SmoothProgramme& x) const;  // with rounded cycles (preferred period)
  SmoothProgramme smooth_of(const TableProfile& profile) const;

  // A first guess: K segments sweeping the domain's temperatures down and up with full-range rate cycles.
  TableProfile initial() const;

 private:
  TableProfile assemble(double start_c, const std::vector<ProfileSegment>& segments) const;
  DesignSpaceOptions o_;
  double t_lo_, t_hi_, w_max_;
};

}  // namespace gyrosid::design
