#include "trajectory/trajectory_config.h"

#include "core/error.h"
#include "core/units.h"
#include "trajectory/calibration_trajectories.h"
#include "trajectory/programme.h"

namespace gyrosid {
namespace {

using units::dps_to_radps;

std::pair<double, double> pair_of(const ConfigNode& node, std::string_view key) {
  const auto v = node.numbers(key);
  if (v.size() != 2 || !(v[1] > v[0])) fail(node.where(key), ": expected [low, high] with low < high");
  return {v[0], v[1]};
}

template <typename Options>
Options validated(Options o, const ConfigNode& node) {
  if (auto p = o.validate(); !p.empty()) fail(node.where(), ": ", p);
  return o;
}

}  // namespace

TrajectorySpec load_trajectory(const ConfigNode& node) {
  const CalibrationKind kind = parse_enum<CalibrationKind>(node.text("kind"), node.where("kind"));
  std::vector<std::string_view> common = {"kind", "name", "description", "latitude_deg", "chamber", "sampling", "position"};
  auto allow = [&](std::initializer_list<std::string_view> extra) {
    // allow_only takes an initializer list; check against common + extra by hand.
    for (const auto& key : node.keys()) {
      bool ok = false;
      for (auto c : common) ok = ok || c == key;
      for (auto e : extra) ok = ok || e == key;
      if (!ok) {
        std::string list;
        for (auto c : common) list += std::string(list.empty() ? "" : ", ") + std::string(c);
        for (auto e : extra) list += ", " + std::string(e);
        fail(node.where(key), ": unknown key '", key, "' for a ", to_string(kind), " trajectory; allowed: ", list);
      }
    }
  };
  const int position = node.integer("position", 2);

  TrajectorySpec spec;
  switch (kind) {
    case CalibrationKind::static_run: {
      allow({"temperature_c", "duration_min", "rate_dps"});
      StaticOptions o;
      o.temp_c = node.number("temperature_c", 25.0);
      o.duration_s = node.number("duration_min") * 60.0;
      o.rate_radps = dps_to_radps(node.number("rate_dps", 0.0));
      o.position = position;
      spec.profile = static_profile(validated(o, node));
      break;
    }
    case CalibrationKind::thermal_ramp: {
      allow({"temperature_c", "rate_c_per_min", "hold_start_min", "hold_end_min", "rate_dps"});
      RampOptions o;
      const auto t = node.numbers("temperature_c");
      if (t.size() != 2) fail(node.where("temperature_c"), ": expected [start, end]");
      o.temp_start_c = t[0];
      o.temp_end_c = t[1];
      o.rate_c_per_min = node.number("rate_c_per_min", 5.0);
      o.hold_start_min = node.number("hold_start_min", 0.0);
      o.hold_end_min = node.number("hold_end_min", 0.0);
      o.table_rate_radps = dps_to_radps(node.number("rate_dps", 0.0));
      o.position = position;
      spec.profile = thermal_ramp(validated(o, node));
      break;
    }
    case CalibrationKind::classical_soak: {
      allow({"plateaus_c", "ramp_rate_c_per_min", "settle_min", "positions", "rates_dps", "step_dwell_s"});
      SoakOptions o;
      o.plateaus_c = node.numbers("plateaus_c");
      o.ramp_rate_c_per_min = node.number("ramp_rate_c_per_min", 5.0);
      o.settle_min = node.number("settle_min", 30.0);
      o.positions = node.integers("positions", {1, 2, 3, 4, 5, 6});
      for (double r : node.numbers("rates_dps")) o.rates_radps.push_back(dps_to_radps(r));
      o.step_dwell_s = node.number("step_dwell_s", 20.0);
      spec.profile = classical_soak(validated(o, node));
      break;
    }
    case CalibrationKind::single_scan:
    case CalibrationKind::dual_scan:
    case CalibrationKind::test_cycles: {
      if (kind == CalibrationKind::single_scan) {
        allow({"temperature_c", "scan_rate_c_per_min", "rate_dps", "rate_cycles_per_scan", "boundary_scan_min", "direction"});
      } else if (kind == CalibrationKind::dual_scan) {
        allow({"temperature_c", "scan_rate_c_per_min", "rate_dps", "rate_cycles_per_scan", "boundary_scan_min"});
      } else {
        allow({"temperature_c", "scan_rate_c_per_min", "rate_dps", "temperature_cycles",
               "rate_cycles_per_temperature_cycle", "boundary_scan_min"});
      }
      ScanOptions o;
      std::tie(o.temp_low_c, o.temp_high_c) = pair_of(node, "temperature_c");
      o.scan_rate_c_per_min = node.number("scan_rate_c_per_min", 5.0);
      const auto [lo, hi] = pair_of(node, "rate_dps");
      o.rate_low_radps = dps_to_radps(lo);
      o.rate_high_radps = dps_to_radps(hi);
      o.boundary_scan_min = node.number("boundary_scan_min", 2.0);
      o.position = position;
      if (kind == CalibrationKind::test_cycles) {
        o.temperature_cycles = node.integer("temperature_cycles");
        // m rate cycles per temperature cycle = m/2 per scan (one up, one down)
        o.rate_cycles_per_scan = 0.5 * node.number("rate_cycles_per_temperature_cycle");
      } else {
        o.rate_cycles_per_scan = node.number("rate_cycles_per_scan");
      }
      if (kind == CalibrationKind::single_scan) {
        const std::string direction = node.text("direction", "up");
        if (direction != "up" && direction != "down") fail(node.where("direction"), ": expected up or down, found '", direction, "'");
        o.start_low = direction == "up";
      }
      validated(o, node);
      spec.profile = kind == CalibrationKind::single_scan ? single_scan(o)
                     : kind == CalibrationKind::dual_scan ? dual_scan(o)
                                                          : test_cycles(o);
      break;
    }
    case CalibrationKind::programme:
      allow({"segments"});
      spec.profile.kind = "programme";
      spec.profile.segments = load_programme_segments(node, position);
      break;
  }
  spec.profile.name = node.text("name", to_string(kind).data());
  spec.description = node.text("description", "");
  spec.profile.latitude_rad = units::deg_to_rad(node.number("latitude_deg", 0.0));
  if (auto chamber = node.find("chamber")) {
    chamber->allow_only({"rate_limit_c_per_min", "min_c", "max_c"});
    spec.profile.limits.rate_limit_c_per_min = chamber->number("rate_limit_c_per_min", 5.0);
    spec.profile.limits.min_c = chamber->number("min_c", -70.0);
    spec.profile.limits.max_c = chamber->number("max_c", 180.0);
  }
  if (auto p = spec.profile.check_limits(); !p.empty()) fail(node.where(), ": ", p);
  const ConfigNode sampling = node["sampling"];
  sampling.allow_only({"samples", "rate_hz"});
  spec.sampling.samples = static_cast<std::size_t>(sampling.integer("samples", 0));
  spec.sampling.rate_hz = sampling.number("rate_hz", 0.0);
  if (sampling.integer("samples", 0) < 0) fail(sampling.where("samples"), ": must be positive");
  if (auto p = spec.sampling.validate(); !p.empty()) fail(sampling.where(), ": ", p);
  return spec;
}

TrajectorySpec load_trajectory_file(const std::string& path) { return load_trajectory(ConfigNode::load(path)); }

}  // namespace gyrosid
