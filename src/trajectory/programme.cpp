#include "trajectory/programme.h"

#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid {
namespace {

using units::dps_to_radps;
using units::radps_to_dps;

RateProfile load_rate(const ConfigNode& segment) {
  const ConfigNode rate = segment["rate_dps"];
  if (rate.is_scalar()) return RateProfile::constant(dps_to_radps(rate.as_number()));
  if (!rate.is_map()) fail(rate.where(), ": expected a rate in deg/s or {triangle: [low, high], cycles, phase}");
  rate.allow_only({"triangle", "cycles", "phase"});
  const auto range = rate.numbers("triangle");
  if (range.size() != 2 || !(range[1] >= range[0])) fail(rate.where("triangle"), ": expected [low, high] with low <= high");
  const double cycles = rate.number("cycles"), phase = rate.number("phase", 0.0);
  if (!(cycles > 0)) fail(rate.where("cycles"), ": must be positive");
  if (!(phase >= 0 && phase < 1)) fail(rate.where("phase"), ": must be in [0, 1)");
  return RateProfile::triangle(dps_to_radps(range[0]), dps_to_radps(range[1]), cycles, phase);
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

}  // namespace

std::vector<ProfileSegment> load_programme_segments(const ConfigNode& node, int default_position) {
  const ConfigNode list = node["segments"];
  if (!list.is_sequence() || list.size() == 0) fail(list.where(), ": expected a non-empty list of segments");
  std::vector<ProfileSegment> segments;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ConfigNode s = list.at(i);
    s.allow_only({"label", "duration_min", "chamber_c", "rate_dps", "position"});
    ProfileSegment seg;
    seg.label = s.text("label", str_cat("segment ", i + 1));
    seg.duration_s = s.number("duration_min") * 60.0;
    if (!(seg.duration_s > 0)) fail(s.where("duration_min"), ": must be positive");
    const ConfigNode chamber = s["chamber_c"];
    const std::vector<double> temps = chamber.is_scalar() ? std::vector<double>{chamber.as_number()} : chamber.as_numbers();
    if (temps.empty() || temps.size() > 2) fail(chamber.where(), ": expected a temperature or [start, end]");
    seg.chamber_start_c = temps.front();
    seg.chamber_end_c = temps.back();
    seg.rate = load_rate(s);
    seg.position = static_cast<int>(s.integer("position", default_position));
    segments.push_back(std::move(seg));
  }
  return segments;
}

std::string programme_yaml(const TrajectorySpec& spec) {
  const TableProfile& p = spec.profile;
  const auto n = format_number;
  std::ostringstream out;
  out << "# " << (p.kind == "programme" ? "Calibration programme" : "The " + p.kind + " trajectory written as a programme")
      << ": " << format_significant(p.duration_min(), 6) << " min, " << p.segments.size() << " segments.\n";
  out << "kind: programme\nname: " << quoted(p.name) << "\n";
  if (!spec.description.empty()) out << "description: " << quoted(spec.description) << "\n";
  out << "latitude_deg: " << n(units::rad_to_deg(p.latitude_rad)) << "\n";
  out << "chamber: {rate_limit_c_per_min: " << n(p.limits.rate_limit_c_per_min)
      << (p.limits.limit_c_per_min(false) == p.limits.rate_limit_c_per_min ? "" : ", cooling_limit_c_per_min: " + n(p.limits.cooling_limit_c_per_min))
      << ", min_c: " << n(p.limits.min_c) << ", max_c: " << n(p.limits.max_c) << "}\n";
  if (std::isfinite(p.table_limits.max_acceleration_radps2)) {
    out << "table: {max_acceleration_dps2: " << n(radps_to_dps(p.table_limits.max_acceleration_radps2)) << "}\n";
  }
  out << "segments:\n";
  for (const auto& s : p.segments) {
    out << "  - {label: " << quoted(s.label) << ", duration_min: " << n(s.duration_s / 60.0) << ", chamber_c: ["
        << n(s.chamber_start_c) << ", " << n(s.chamber_end_c) << "], rate_dps: ";
    if (s.rate.shape == RateProfile::Shape::constant) {
      out << n(radps_to_dps(s.rate.value_radps));
    } else {
      out << "{triangle: [" << n(radps_to_dps(s.rate.low_radps)) << ", " << n(radps_to_dps(s.rate.high_radps))
          << "], cycles: " << n(s.rate.cycles) << ", phase: " << n(s.rate.phase) << "}";
    }
    out << ", position: " << s.position << "}\n";
  }
  if (spec.sampling.samples > 0) out << "sampling: {samples: " << spec.sampling.samples << "}\n";
  else out << "sampling: {rate_hz: " << n(spec.sampling.rate_hz) << "}\n";
  return out.str();
}

}  // namespace gyrosid
