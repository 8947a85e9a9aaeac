#include "trajectory/trajectory_config.h"

#include <map>

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

// The keys every trajectory kind takes, besides its own.
const std::vector<std::string> kCommonKeys = {"kind", "name", "description", "latitude_deg", "chamber", "table", "sampling", "position"};

TableProfile read_static(const ConfigNode& node, int position) {
  StaticOptions o;
  o.temp_c = node.number("temperature_c", 25.0);
  o.duration_s = node.number("duration_min") * 60.0;
  o.rate_radps = dps_to_radps(node.number("rate_dps", 0.0));
  o.position = position;
  return static_profile(validated(o, node));
}

TableProfile read_ramp(const ConfigNode& node, int position) {
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
  return thermal_ramp(validated(o, node));
}

TableProfile read_soak(const ConfigNode& node, int /*position: the soak visits its own positions*/) {
  SoakOptions o;
  o.plateaus_c = node.numbers("plateaus_c");
  o.ramp_rate_c_per_min = node.number("ramp_rate_c_per_min", 5.0);
  o.settle_min = node.number("settle_min", 30.0);
  o.positions = node.integers("positions", {1, 2, 3, 4, 5, 6});
  for (double r : node.numbers("rates_dps")) o.rates_radps.push_back(dps_to_radps(r));
  o.step_dwell_s = node.number("step_dwell_s", 20.0);
  return classical_soak(validated(o, node));
}

// The temperature and rate scans shared by the single scan, the dual scan and the test cycles.
ScanOptions read_scan(const ConfigNode& node, int position) {
  ScanOptions o;
  std::tie(o.temp_low_c, o.temp_high_c) = pair_of(node, "temperature_c");
  o.scan_rate_c_per_min = node.number("scan_rate_c_per_min", 5.0);
  const auto [lo, hi] = pair_of(node, "rate_dps");
  o.rate_low_radps = dps_to_radps(lo);
  o.rate_high_radps = dps_to_radps(hi);
  o.boundary_scan_min = node.number("boundary_scan_min", 2.0);
  o.position = position;
  return o;
}

TableProfile read_single_scan(const ConfigNode& node, int position) {
  ScanOptions o = read_scan(node, position);
  o.rate_cycles_per_scan = node.number("rate_cycles_per_scan");
  const std::string direction = node.text("direction", "up");
  if (direction != "up" && direction != "down") fail(node.where("direction"), ": expected up or down, found '", direction, "'");
  o.start_low = direction == "up";
  return single_scan(validated(o, node));
}

TableProfile read_dual_scan(const ConfigNode& node, int position) {
  ScanOptions o = read_scan(node, position);
  o.rate_cycles_per_scan = node.number("rate_cycles_per_scan");
  return dual_scan(validated(o, node));
}

TableProfile read_test_cycles(const ConfigNode& node, int position) {
  ScanOptions o = read_scan(node, position);
  o.temperature_cycles = node.integer("temperature_cycles");
  // m rate cycles per temperature cycle = m/2 per scan (one up, one down)
  o.rate_cycles_per_scan = 0.5 * node.number("rate_cycles_per_temperature_cycle");
  return test_cycles(validated(o, node));
}

TableProfile read_programme(const ConfigNode& node, int position) {
  TableProfile profile;
  profile.kind = "programme";
  profile.segments = load_programme_segments(node, position);
  return profile;
}

struct KindReader {
  std::vector<std::string> keys;  // besides kCommonKeys
  TableProfile (*read)(const ConfigNode& node, int position);
};

const KindReader& reader_of(CalibrationKind kind) {
  static const std::map<CalibrationKind, KindReader> readers = {
      {CalibrationKind::static_run, {{"temperature_c", "duration_min", "rate_dps"}, read_static}},
      {CalibrationKind::thermal_ramp, {{"temperature_c", "rate_c_per_min", "hold_start_min", "hold_end_min", "rate_dps"}, read_ramp}},
      {CalibrationKind::classical_soak,
       {{"plateaus_c", "ramp_rate_c_per_min", "settle_min", "positions", "rates_dps", "step_dwell_s"}, read_soak}},
      {CalibrationKind::single_scan,
       {{"temperature_c", "scan_rate_c_per_min", "rate_dps", "rate_cycles_per_scan", "boundary_scan_min", "direction"}, read_single_scan}},
      {CalibrationKind::dual_scan,
       {{"temperature_c", "scan_rate_c_per_min", "rate_dps", "rate_cycles_per_scan", "boundary_scan_min"}, read_dual_scan}},
      {CalibrationKind::test_cycles,
       {{"temperature_c", "scan_rate_c_per_min", "rate_dps", "temperature_cycles", "rate_cycles_per_temperature_cycle", "boundary_scan_min"},
        read_test_cycles}},
      {CalibrationKind::programme, {{"segments"}, read_programme}},
  };
  return readers.at(kind);
}

ChamberLimits read_chamber(const ConfigNode& node) {
  ChamberLimits limits;
  if (auto chamber = node.find("chamber")) {
    chamber->allow_only({"rate_limit_c_per_min", "cooling_limit_c_per_min", "min_c", "max_c"});
    limits.rate_limit_c_per_min = chamber->number("rate_limit_c_per_min", limits.rate_limit_c_per_min);
    limits.cooling_limit_c_per_min = chamber->number("cooling_limit_c_per_min", limits.cooling_limit_c_per_min);
    limits.min_c = chamber->number("min_c", limits.min_c);
    limits.max_c = chamber->number("max_c", limits.max_c);
  }
  return limits;
}

TableLimits read_table_limits(const ConfigNode& node) {
  TableLimits limits;
  if (auto table = node.find("table")) {
    table->allow_only({"max_acceleration_dps2"});
    const double a = table->number("max_acceleration_dps2", INFINITY);
    if (!(a > 0)) fail(table->where("max_acceleration_dps2"), ": must be positive");
    limits.max_acceleration_radps2 = units::dps_to_radps(a);
  }
  return limits;
}

Sampling read_sampling(const ConfigNode& node) {
  const ConfigNode sampling = node["sampling"];
  sampling.allow_only({"samples", "rate_hz"});
  Sampling out;
  const int samples = sampling.integer("samples", 0);
  if (samples < 0) fail(sampling.where("samples"), ": must be positive");
  out.samples = static_cast<std::size_t>(samples);
  out.rate_hz = sampling.number("rate_hz", 0.0);
  if (auto p = out.validate(); !p.empty()) fail(sampling.where(), ": ", p);
  return out;
}

}  // namespace

TrajectorySpec load_trajectory(const ConfigNode& node) {
  const CalibrationKind kind = parse_enum<CalibrationKind>(node.text("kind"), node.where("kind"));
  const KindReader& reader = reader_of(kind);
  std::vector<std::string> allowed = kCommonKeys;
  allowed.insert(allowed.end(), reader.keys.begin(), reader.keys.end());
  node.allow_only(allowed);

  TrajectorySpec spec;
  spec.profile = reader.read(node, node.integer("position", 2));
  spec.profile.name = node.text("name", to_string(kind).data());
  spec.description = node.text("description", "");
  spec.profile.latitude_rad = units::deg_to_rad(node.number("latitude_deg", 0.0));
  spec.profile.limits = read_chamber(node);
  spec.profile.table_limits = read_table_limits(node);
  if (auto p = spec.profile.check_limits(); !p.empty()) fail(node.where(), ": ", p);
  spec.sampling = read_sampling(node);
  return spec;
}

TrajectorySpec load_trajectory_file(const std::string& path) { return load_trajectory(ConfigNode::load(path)); }

}  // namespace gyrosid
