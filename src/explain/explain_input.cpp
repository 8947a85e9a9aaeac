#include "explain/explain_input.h"

#include <algorithm>
#include <cmath>

#include "core/axis_view.h"
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

std::optional<std::pair<Eigen::Index, Eigen::Index>> ExplainInput::heldout_run_at(double t_s) const {
  // A change's time is placed to a few rows at best (each row moves the training fit by one sample's worth),
  // so the search can stop a few rows past a held-out run's edge: on a static log, 0.3 s (one row) after it.
  constexpr Eigen::Index kSlack = 10;
  const auto n = size();
  const auto at = static_cast<Eigen::Index>(std::lower_bound(signals.t_s.begin(), signals.t_s.end(), t_s) - signals.t_s.begin());
  const auto held = [&](Eigen::Index i) { return i >= 0 && i < n && heldout[static_cast<std::size_t>(i)] != 0; };
  Eigen::Index first = -1;
  for (Eigen::Index d = 0; d <= kSlack && first < 0; ++d) first = held(at + d) ? at + d : held(at - 1 - d) ? at - 1 - d : -1;
  if (first < 0) return std::nullopt;
  Eigen::Index last = first;
  while (held(first - 1)) --first;
  while (held(last + 1)) ++last;
  return std::make_pair(first, last);
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

ExplainInput load_input(const Recording& recording, const InputOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("explain: ", p);
  ExplainInput in;
  in.source = recording.source();
  NamedColumns other_references;  // a triad's other axes: cross-axis channels
  const Recording rec = single_axis_view(recording, o.axis, &other_references);

  const std::size_t n = rec.rows();
  if (n < 100) fail(rec.source(), ": ", n, " samples; explaining a recording needs at least 100");
  Signals& s = in.signals;
  s.t_s = rec.column("t_s");
  s.rate = vec(rec.column("ref_rate_dps"), units::kDegToRad);
  // Without a thermometer the temperature is held (at 0 C): no temperature effect is testable, as on a
  // recording at one temperature, and the summary says it was not recorded.
  in.temperature_recorded = rec.has("temp_c");
  s.temp_c = in.temperature_recorded ? vec(rec.column("temp_c")) : Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  in.error = vec(rec.column("gyro_dps"), units::kDegToRad) - s.rate;

  // Channels: specific force, magnetic field, the other axes' true rates (triads), auxiliaries.
  for (auto& [name, values] : other_references) {
    if (has_nan(values)) {
      in.skipped.push_back(name + " (has nan: not measured at every sample)");
      continue;
    }
    s.channels[name] = vec(values, units::kDegToRad);
    in.cross_axis.push_back(name);
  }
  const std::vector<std::string> known = {"t_s", "gyro_dps", "temp_c", "position_id", "chamber_temp_c"};
  for (const auto& name : rec.names()) {
    if (std::find(known.begin(), known.end(), name) != known.end() || name.rfind("ref_rate", 0) == 0) continue;
    const auto& values = rec.column(name);
    if (has_nan(values)) {
      in.skipped.push_back(name + " (has nan: not measured at every sample)");
      continue;
    }
    if (name.rfind("accel_", 0) == 0 && ends_with(name, "_mps2")) {
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
