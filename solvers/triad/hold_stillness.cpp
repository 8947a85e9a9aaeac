#include "solvers/triad/hold_stillness.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

std::vector<HoldStillness> HoldStillnessCheck::not_still() const {
  std::vector<HoldStillness> out;
  for (const auto& h : holds) {
    if (!h.still) out.push_back(h);
  }
  return out;
}

namespace {

std::string three(const std::array<double, 3>& v) {
  return str_cat(format_significant(v[0], 3), "/", format_significant(v[1], 3), "/", format_significant(v[2], 3));
}

}  // namespace

std::string HoldStillnessCheck::describe(const HoldStillness& h) const {
  return str_cat("hold position_id ", h.position_id, " (", format_significant(h.t_start_s, 6), " s to ", format_significant(h.t_end_s, 6),
                 " s) is not still: gyro std x/y/z ", three(h.gyro_std_dps), " deg/s, ", format_significant(h.ratio, 3),
                 "x the quietest hold's (position_id ", quietest_position_id, ": ", three(floor_dps),
                 " deg/s); motion in a hold corrupts the biases and the gravity directions of the turns around it");
}

nlohmann::json HoldStillnessCheck::json() const {
  nlohmann::json bad = nlohmann::json::array();
  for (const auto& h : not_still()) {
    bad.push_back({{"position_id", h.position_id}, {"t_start_s", h.t_start_s}, {"t_end_s", h.t_end_s}, {"samples", h.samples},
                   {"gyro_std_dps", h.gyro_std_dps}, {"ratio", h.ratio}});
  }
  return {{"holds_checked", holds.size()},
          {"floor_dps", floor_dps},
          {"quietest_position_id", quietest_position_id},
          {"ratio_limit", ratio_limit},
          {"not_still", bad},
          {"criterion", str_cat("a hold is not still when its gyro's standard deviation on some axis exceeds ", format_significant(ratio_limit, 3),
                                "x the quietest hold's on that axis (solvers/triad/hold_stillness.h)")}};
}

HoldStillnessCheck check_hold_stillness(const TriadData& d, double ratio_limit) {
  HoldStillnessCheck c;
  c.ratio_limit = ratio_limit;
  const auto n = static_cast<std::size_t>(d.size());
  for (std::size_t begin = 0; begin < n && !d.position_id.empty();) {
    std::size_t end = begin;
    while (end < n && d.position_id[end] == d.position_id[begin]) ++end;
    if (d.position_id[begin] != 0 && end - begin >= kMinHoldSamples) {
      HoldStillness h;
      h.position_id = d.position_id[begin];
      h.t_start_s = d.t_s[begin], h.t_end_s = d.t_s[end - 1];
      h.samples = end - begin;
      const auto rows = d.gyro.middleRows(static_cast<Eigen::Index>(begin), static_cast<Eigen::Index>(end - begin));
      const Eigen::RowVector3d mean = rows.colwise().mean();
      for (int i = 0; i < 3; ++i) {
        const double ss = (rows.col(i).array() - mean(i)).square().sum();
        h.gyro_std_dps[static_cast<std::size_t>(i)] = units::radps_to_dps(std::sqrt(ss / static_cast<double>(h.samples - 1)));
      }
      c.holds.push_back(h);
    }
    begin = end;
  }
  if (c.holds.empty()) return c;
  double quietest = std::numeric_limits<double>::infinity();
  c.floor_dps.fill(std::numeric_limits<double>::infinity());
  for (const auto& h : c.holds) {
    double rms = 0.0;
    for (std::size_t i = 0; i < 3; ++i) c.floor_dps[i] = std::min(c.floor_dps[i], h.gyro_std_dps[i]), rms += h.gyro_std_dps[i] * h.gyro_std_dps[i];
    if (rms < quietest) quietest = rms, c.quietest_position_id = h.position_id;
  }
  for (auto& h : c.holds) {
    for (std::size_t i = 0; i < 3; ++i) {
      const double r = c.floor_dps[i] > 0 ? h.gyro_std_dps[i] / c.floor_dps[i] : (h.gyro_std_dps[i] > 0 ? std::numeric_limits<double>::infinity() : 1.0);
      h.ratio = std::max(h.ratio, r);
    }
    const double largest = *std::max_element(h.gyro_std_dps.begin(), h.gyro_std_dps.end());
    h.still = !(h.ratio > ratio_limit && largest > kStillnessResolutionDps);
  }
  return c;
}

}  // namespace gyrosid
