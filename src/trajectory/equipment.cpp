#include "trajectory/equipment.h"

#include <cmath>
#include <sstream>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {
namespace {

double positive(const ConfigNode& node, const char* key, double fallback) {
  const double v = node.number(key, fallback);
  if (!(v > 0)) fail(node.where(key), ": must be positive");
  return v;
}

}  // namespace

Equipment load_equipment(const std::string& path) {
  const ConfigNode root = ConfigNode::load(path);
  root.allow_only({"kind", "name", "chamber", "table"});
  if (const std::string kind = root.text("kind"); kind != "equipment") fail(root.where("kind"), ": expected 'equipment', got '", kind, "'");
  Equipment e;
  e.name = root.text("name", path);
  if (const auto c = root.find("chamber")) {
    c->allow_only({"min_c", "max_c", "heating_c_per_min", "cooling_c_per_min"});
    e.chamber.min_c = c->number("min_c", e.chamber.min_c);
    e.chamber.max_c = c->number("max_c", e.chamber.max_c);
    if (!(e.chamber.min_c < e.chamber.max_c)) fail(c->where("max_c"), ": the chamber's range must have min_c below max_c");
    e.chamber.rate_limit_c_per_min = positive(*c, "heating_c_per_min", e.chamber.rate_limit_c_per_min);
    e.chamber.cooling_limit_c_per_min = positive(*c, "cooling_c_per_min", e.chamber.rate_limit_c_per_min);
  }
  if (const auto t = root.find("table")) {
    t->allow_only({"max_rate_dps", "max_acceleration_dps2", "slip_ring"});
    e.table_max_rate_radps = units::dps_to_radps(positive(*t, "max_rate_dps", INFINITY));
    e.table.max_acceleration_radps2 = units::dps_to_radps(positive(*t, "max_acceleration_dps2", INFINITY));
    if (!t->flag("slip_ring", true)) {
      fail(t->where("slip_ring"), ": a table without a slip ring is not supported yet (designs turn the table without a travel limit)");
    }
  }
  return e;
}

std::string setpoint_table_csv(const TableProfile& p) {
  std::ostringstream out;
  out << "t_s,chamber_setpoint_c,table_rate_dps,position\n";
  const auto row = [&](double t, double temp, double rate, int position) {
    out << format_number(t) << "," << format_number(temp) << "," << format_number(units::radps_to_dps(rate)) << "," << position << "\n";
  };
  double start = 0.0;
  for (const ProfileSegment& s : p.segments) {
    const auto emit = [&](double tau) {
      const double temp = s.chamber_start_c + (s.chamber_end_c - s.chamber_start_c) * tau / s.duration_s;
      row(start + tau, temp, s.rate.at(tau, s.duration_s), s.position);
    };
    emit(0.0);
    if (s.rate.shape == RateProfile::Shape::triangle && s.rate.cycles > 0) {
      // Vertices where the cycle fraction phase + cycles tau / duration crosses a multiple of 1/2.
      const double half = s.duration_s / (2.0 * s.rate.cycles);
      for (double k = std::floor(2.0 * s.rate.phase) + 1.0;; k += 1.0) {
        const double tau = (k / 2.0 - s.rate.phase) * 2.0 * half;
        if (tau >= s.duration_s - 1e-9 * s.duration_s) break;
        emit(tau);
      }
    }
    emit(s.duration_s);
    start += s.duration_s;
  }
  return out.str();
}

}  // namespace gyrosid
