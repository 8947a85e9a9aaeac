#include "trajectory/calibration_trajectories.h"

#include <cmath>

#include "core/error.h"

namespace gyrosid {
namespace {

void check(const std::string& problem, const char* what) {
  if (!problem.empty()) fail(what, ": ", problem);
}

ProfileSegment hold(std::string label, double minutes, double temp_c, RateProfile rate, int position) {
  return {std::move(label), minutes * 60.0, temp_c, temp_c, rate, position};
}

ProfileSegment ramp(std::string label, double from_c, double to_c, double rate_c_per_min, RateProfile rate,
                    int position) {
  return {std::move(label), std::abs(to_c - from_c) / rate_c_per_min * 60.0, from_c, to_c, rate, position};
}

// One temperature scan with rate cycling; `phase` of the rate triangle at its start.
ProfileSegment scan(const ScanOptions& o, std::string label, double from_c, double to_c, double cycles, double phase) {
  return ramp(std::move(label), from_c, to_c, o.scan_rate_c_per_min,
              RateProfile::triangle(o.rate_low_radps, o.rate_high_radps, cycles, phase), o.position);
}

void add_boundary(const ScanOptions& o, TableProfile& p, const std::string& label, double temp_c) {
  if (o.boundary_scan_min > 0) {
    p.segments.push_back(hold(label, o.boundary_scan_min, temp_c,
                              RateProfile::triangle(o.rate_low_radps, o.rate_high_radps, 1.0, 0.0), o.position));
  }
}

}  // namespace

std::string StaticOptions::validate() const {
  if (!(duration_s > 0)) return str_cat("duration_s = ", duration_s, " must be positive");
  return "";
}

std::string RampOptions::validate() const {
  if (!(rate_c_per_min > 0)) return str_cat("rate_c_per_min = ", rate_c_per_min, " must be positive");
  if (temp_start_c == temp_end_c) return "the ramp needs different start and end temperatures";
  if (hold_start_min < 0 || hold_end_min < 0) return "hold times must be >= 0";
  return "";
}

std::string SoakOptions::validate() const {
  if (plateaus_c.empty()) return "needs at least one plateau";
  if (!(ramp_rate_c_per_min > 0)) return "ramp_rate_c_per_min must be positive";
  if (settle_min < 0) return "settle_min must be >= 0";
  if (positions.empty()) return "needs at least one mount position";
  if (rates_radps.empty()) return "needs at least one table rate (use 0 for a static dwell)";
  if (!(step_dwell_s > 0)) return "step_dwell_s must be positive";
  return "";
}

std::string ScanOptions::validate() const {
  if (!(temp_high_c > temp_low_c)) return str_cat("temperature range [", temp_low_c, ", ", temp_high_c, "] is empty");
  if (!(scan_rate_c_per_min > 0)) return "scan_rate_c_per_min must be positive";
  if (!(rate_high_radps > rate_low_radps)) return "rate range must have low < high";
  if (!(rate_cycles_per_scan > 0)) return "rate_cycles_per_scan must be positive";
  if (boundary_scan_min < 0) return "boundary_scan_min must be >= 0";
  if (temperature_cycles < 1) return "temperature_cycles must be >= 1";
  return "";
}

TableProfile static_profile(const StaticOptions& o) {
  check(o.validate(), "static trajectory");
  TableProfile p;
  p.kind = "static";
  p.segments.push_back(hold("static", o.duration_s / 60.0, o.temp_c, RateProfile::constant(o.rate_radps), o.position));
  return p;
}

TableProfile thermal_ramp(const RampOptions& o) {
  check(o.validate(), "thermal ramp");
  TableProfile p;
  p.kind = "thermal_ramp";
  const RateProfile rate = RateProfile::constant(o.table_rate_radps);
  if (o.hold_start_min > 0) p.segments.push_back(hold("hold start", o.hold_start_min, o.temp_start_c, rate, o.position));
  p.segments.push_back(ramp("ramp", o.temp_start_c, o.temp_end_c, o.rate_c_per_min, rate, o.position));
  if (o.hold_end_min > 0) p.segments.push_back(hold("hold end", o.hold_end_min, o.temp_end_c, rate, o.position));
  return p;
}

TableProfile classical_soak(const SoakOptions& o) {
  check(o.validate(), "classical soak");
  TableProfile p;
  p.kind = "classical_soak";
  for (std::size_t i = 0; i < o.plateaus_c.size(); ++i) {
    const double temp = o.plateaus_c[i];
    const int position = o.positions.front();
    if (i > 0) {
      p.segments.push_back(ramp(str_cat("ramp to ", temp, " C"), o.plateaus_c[i - 1], temp, o.ramp_rate_c_per_min,
                                RateProfile::constant(0.0), position));
    }
    if (o.settle_min > 0) {
      p.segments.push_back(hold(str_cat("settle at ", temp, " C"), o.settle_min, temp, RateProfile::constant(0.0), position));
    }
    for (int pos : o.positions) {
      for (double rate : o.rates_radps) {
        p.segments.push_back(hold(str_cat(temp, " C, position ", pos), o.step_dwell_s / 60.0, temp,
                                  RateProfile::constant(rate), pos));
      }
    }
  }
  return p;
}

TableProfile single_scan(const ScanOptions& o) {
  check(o.validate(), "single scan");
  TableProfile p;
  p.kind = "single_scan";
  const double from = o.start_low ? o.temp_low_c : o.temp_high_c, to = o.start_low ? o.temp_high_c : o.temp_low_c;
  add_boundary(o, p, "boundary scan (start)", from);
  p.segments.push_back(scan(o, "scan", from, to, o.rate_cycles_per_scan, 0.0));
  add_boundary(o, p, "boundary scan (end)", to);
  return p;
}

TableProfile dual_scan(const ScanOptions& o) {
  check(o.validate(), "dual scan");
  TableProfile p;
  p.kind = "dual_scan";
  // Down-scan phase 1/2: the triangle is even, so with whole cycles per scan the rate at each temperature
  // on the way down is half a cycle away from the rate at that temperature on the way up.
  add_boundary(o, p, "boundary scan (low)", o.temp_low_c);
  p.segments.push_back(scan(o, "up scan", o.temp_low_c, o.temp_high_c, o.rate_cycles_per_scan, 0.0));
  add_boundary(o, p, "boundary scan (high)", o.temp_high_c);
  p.segments.push_back(scan(o, "down scan", o.temp_high_c, o.temp_low_c, o.rate_cycles_per_scan, 0.5));
  add_boundary(o, p, "boundary scan (low)", o.temp_low_c);
  return p;
}

TableProfile test_cycles(const ScanOptions& o) {
  check(o.validate(), "test trajectory");
  TableProfile p;
  p.kind = "test_cycles";
  const int n = o.temperature_cycles;
  for (int c = 0; c < n; ++c) {
    const double shift = 0.5 * c / n;  // cycle c fills the gaps of the previous ones
    if (c == 0) add_boundary(o, p, "boundary scan (low)", o.temp_low_c);
    p.segments.push_back(scan(o, str_cat("cycle ", c + 1, " up"), o.temp_low_c, o.temp_high_c, o.rate_cycles_per_scan, shift));
    add_boundary(o, p, "boundary scan (high)", o.temp_high_c);
    p.segments.push_back(
        scan(o, str_cat("cycle ", c + 1, " down"), o.temp_high_c, o.temp_low_c, o.rate_cycles_per_scan, 0.5 + shift));
    add_boundary(o, p, "boundary scan (low)", o.temp_low_c);
  }
  return p;
}

}  // namespace gyrosid
