#include "explain/explain_input.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/recording.h"
#include "core/units.h"

namespace gyrosid::explain {

std::string InputOptions::validate() const {
  if (!axis.empty() && axis != "x" && axis != "y" && axis != "z") return str_cat("axis '", axis, "' must be x, y or z");
  if (heldout_every < 2) return "heldout_every must be at least 2";
  return "";
}

Eigen::Index ExplainInput::training_size() const {
  return static_cast<Eigen::Index>(std::count(heldout.begin(), heldout.end(), 0));
}

namespace {

Eigen::VectorXd vec(const std::vector<double>& v, double scale = 1.0) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())) * scale;
}

bool has_nan(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return std::isnan(x); });
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Turning points of the temperature (moving-average smoothed over +-60 s) that move it by at least
// `excursion`; returns the sample indices of the minima.
std::vector<std::size_t> temperature_minima(const std::vector<double>& t, const std::vector<double>& temp, double excursion) {
  const std::size_t n = t.size();
  std::vector<double> smooth(n);
  std::size_t lo = 0, hi = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    while (hi < n && t[hi] <= t[i] + 60.0) sum += temp[hi++];
    while (t[lo] < t[i] - 60.0) sum -= temp[lo++];
    smooth[i] = sum / static_cast<double>(hi - lo);
  }
  // Zig-zag: a valley counts once the temperature has fallen into it and risen out of it by `excursion`.
  std::vector<std::size_t> minima;
  enum { unknown, falling, rising } phase = unknown;
  double high = smooth[0], low = smooth[0];
  std::size_t low_at = 0;
  for (std::size_t i = 1; i < n; ++i) {
    high = std::max(high, smooth[i]);
    if (smooth[i] < low) low = smooth[i], low_at = i;
    if (phase != falling && smooth[i] < high - excursion) {
      phase = falling, low = smooth[i], low_at = i;
    } else if (phase != rising && smooth[i] > low + excursion) {
      if (phase == falling) minima.push_back(low_at);
      phase = rising, high = smooth[i];
    }
  }
  return minima;
}

}  // namespace

ExplainInput load_input(const Recording& rec, const InputOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("explain: ", p);
  ExplainInput in;
  in.source = rec.source();
  const bool triad = rec.kind() == RecordingKind::triad;
  if (triad && o.axis.empty()) fail(rec.source(), ": a triad recording; choose the gyro with --axis x|y|z");
  if (!triad && !o.axis.empty()) fail(rec.source(), ": --axis applies to triad recordings only");
  const std::string gyro = triad ? "gyro_" + o.axis + "_dps" : "gyro_dps";
  const std::string ref = triad ? "ref_rate_" + o.axis + "_dps" : "ref_rate_dps";
  const std::string temp = triad && rec.has("temp_" + o.axis + "_c") ? "temp_" + o.axis + "_c" : "temp_c";

  const std::size_t n = rec.rows();
  if (n < 100) fail(rec.source(), ": ", n, " samples; explaining a recording needs at least 100");
  Signals& s = in.signals;
  s.t_s = rec.column("t_s");
  s.rate = vec(rec.column(ref), units::kDegToRad);
  s.temp_c = vec(rec.column(temp));
  in.error = vec(rec.column(gyro), units::kDegToRad) - s.rate;

  // Channels: specific force, magnetic field, the other axes' true rates (triads), auxiliaries.
  const std::vector<std::string> known = {"t_s", gyro, ref, temp, "gyro_x_dps", "gyro_y_dps", "gyro_z_dps", "temp_x_c", "temp_y_c",
                                          "temp_z_c", "position_id", "chamber_temp_c"};
  for (const auto& name : rec.names()) {
    const bool other_ref = triad && name.rfind("ref_rate_", 0) == 0 && name != ref;
    if (!other_ref && std::find(known.begin(), known.end(), name) != known.end()) continue;
    if (!other_ref && name.rfind("ref_rate", 0) == 0) continue;
    const auto& values = rec.column(name);
    if (has_nan(values)) {
      in.skipped.push_back(name + " (has nan: not measured at every sample)");
      continue;
    }
    if (other_ref) {
      s.channels[name] = vec(values, units::kDegToRad);
      in.cross_axis.push_back(name);
    } else if (name.rfind("accel_", 0) == 0 && ends_with(name, "_mps2")) {
      s.channels[name] = vec(values);
      in.accel.push_back(name);
    } else if (name.find("mag") != std::string::npos && ends_with(name, "_ut")) {
      s.channels[name] = vec(values);
      in.magnetic.push_back(name);
    } else {
      s.channels[name] = vec(values);
      in.aux.push_back(name);
    }
  }

  // Sampling: median interval; segments of uniform sampling.
  in.dt_s = median_sample_interval(s.t_s);
  in.segment.assign(n, 0);
  for (std::size_t i = 1; i < n; ++i) in.segment[i] = in.segment[i - 1] + (s.t_s[i] - s.t_s[i - 1] > 1.5 * in.dt_s ? 1 : 0);

  // Blocks: whole thermal cycles (minimum to minimum) when there are at least four, else eight equal
  // spans of time. Every heldout_every-th block from the third is held out.
  const std::vector<double> probe(s.temp_c.data(), s.temp_c.data() + n);
  const double range = s.temp_c.maxCoeff() - s.temp_c.minCoeff();
  const std::vector<std::size_t> minima = temperature_minima(s.t_s, probe, std::max(2.0, 0.1 * range));
  in.block.assign(n, 0);
  if (minima.size() >= 3) {  // three interior minima: at least four cycles with the partial ends
    in.thermal_cycles = true;
    std::size_t b = 0;
    for (std::size_t i = 0; i < n; ++i) {
      while (b < minima.size() && i >= minima[b]) ++b;
      in.block[i] = static_cast<int>(b);
    }
    in.blocks = static_cast<int>(minima.size()) + 1;
  } else {
    in.blocks = 8;
    const double t0 = s.t_s.front(), span = s.t_s.back() - t0;
    for (std::size_t i = 0; i < n; ++i) in.block[i] = std::min(7, static_cast<int>(8.0 * (s.t_s[i] - t0) / span));
  }
  in.heldout.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) in.heldout[i] = (in.block[i] % o.heldout_every == 2 % o.heldout_every) ? 1 : 0;
  if (in.training_size() < 50) fail(rec.source(), ": too few training samples after holding out blocks");
  return in;
}

}  // namespace gyrosid::explain
