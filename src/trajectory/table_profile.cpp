#include "trajectory/table_profile.h"

#include <algorithm>
#include <cmath>

#include "core/earth.h"
#include "core/error.h"
#include "core/units.h"
#include "core/rotation.h"

namespace gyrosid {
namespace {

// Normalised triangle over one cycle, 0 -> 1 -> 0, and its integral from 0 over p cycles.
double unit_triangle(double p) {
  const double f = p - std::floor(p);
  return f < 0.5 ? 2.0 * f : 2.0 - 2.0 * f;
}
double unit_triangle_integral(double p) {
  const double whole = std::floor(p), f = p - whole;
  return 0.5 * whole + (f < 0.5 ? f * f : 2.0 * f - f * f - 0.5);
}

}  // namespace

RateProfile RateProfile::constant(double radps) {
  RateProfile r;
  r.value_radps = radps;
  return r;
}

RateProfile RateProfile::triangle(double low, double high, double cycles, double phase) {
  RateProfile r;
  r.shape = Shape::triangle;
  r.low_radps = low;
  r.high_radps = high;
  r.cycles = cycles;
  r.phase = phase;
  return r;
}

double RateProfile::at(double tau, double duration) const {
  if (shape == Shape::constant) return value_radps;
  const double p = phase + (duration > 0 ? cycles * tau / duration : 0.0);
  return low_radps + (high_radps - low_radps) * unit_triangle(p);
}

double RateProfile::integral(double tau, double duration) const {
  if (shape == Shape::constant) return value_radps * tau;
  if (cycles == 0 || duration <= 0) return at(0, duration) * tau;
  const double p1 = phase + cycles * tau / duration;
  return low_radps * tau +
         (high_radps - low_radps) * (duration / cycles) * (unit_triangle_integral(p1) - unit_triangle_integral(phase));
}

double TableProfile::duration_s() const {
  double d = 0.0;
  for (const auto& s : segments) d += s.duration_s;
  return d;
}

PiecewiseLinear TableProfile::chamber_temperature() const {
  PiecewiseLinear p;
  double t = 0.0;
  for (const auto& s : segments) {
    p.append(t, s.chamber_start_c);
    t += s.duration_s;
    p.append(t, s.chamber_end_c);
  }
  return p;
}

std::string TableProfile::check_limits() const {
  double t = 0.0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto& s = segments[i];
    const std::string where = str_cat("segment ", i + 1, " ('", s.label, "', starting at ", t / 60.0, " min)");
    if (!(s.duration_s > 0)) return str_cat(where, ": duration must be positive");
    if (i > 0 && std::abs(s.chamber_start_c - segments[i - 1].chamber_end_c) > 1e-9) {
      return str_cat(where, ": the chamber starts at ", s.chamber_start_c, " C but the previous segment ends at ",
                     segments[i - 1].chamber_end_c, " C (the chamber cannot jump)");
    }
    for (double temp : {s.chamber_start_c, s.chamber_end_c}) {
      if (temp < limits.min_c || temp > limits.max_c) {
        return str_cat(where, ": chamber temperature ", temp, " C is outside the chamber range [", limits.min_c, ", ",
                       limits.max_c, "] C");
      }
    }
    const bool heating = s.chamber_end_c >= s.chamber_start_c;
    const double rate = std::abs(s.chamber_end_c - s.chamber_start_c) / (s.duration_s / 60.0);
    if (rate > limits.limit_c_per_min(heating) * (1.0 + 1e-9)) {
      return str_cat(where, ": chamber ", heating ? "heating" : "cooling", " rate ", rate, " C/min exceeds the chamber's limit ",
                     limits.limit_c_per_min(heating), " C/min");
    }
    if (s.rate.shape == RateProfile::Shape::triangle) {
      const double acceleration = 2.0 * (s.rate.high_radps - s.rate.low_radps) * s.rate.cycles / s.duration_s;
      if (acceleration > table_limits.max_acceleration_radps2 * (1.0 + 1e-9)) {
        return str_cat(where, ": table acceleration ", units::radps_to_dps(acceleration), " deg/s^2 exceeds the table's limit ",
                       units::radps_to_dps(table_limits.max_acceleration_radps2), " deg/s^2");
      }
    }
    if (s.position < 1 || s.position > kMountPositions) {
      return str_cat(where, ": mount position ", s.position, " is not 1..", kMountPositions, " (Table 2.1's 1..6, body diagonals 7..10)");
    }
    t += s.duration_s;
  }
  return "";
}

TableProfile concatenate(const TableProfile& first, const TableProfile& then) {
  if (first.segments.empty()) return then;
  if (then.segments.empty()) return first;
  const double end_c = first.segments.back().chamber_end_c, start_c = then.segments.front().chamber_start_c;
  if (std::abs(end_c - start_c) > 1e-9) {
    fail("'", then.name, "' starts the chamber at ", start_c, " C but '", first.name, "' ends at ", end_c, " C: the chamber cannot jump");
  }
  if (std::abs(first.latitude_rad - then.latitude_rad) > 1e-12) fail("'", then.name, "' and '", first.name, "' are on different latitudes");
  TableProfile p = first;
  p.segments.insert(p.segments.end(), then.segments.begin(), then.segments.end());
  return p;
}

Eigen::Matrix3d mount_orientation(int position) {
  const Eigen::Vector3d n(1, 0, 0), e(0, 1, 0), d(0, 0, 1);
  Eigen::Matrix3d c;
  switch (position) {
    case 1: c << n, e, d; break;
    case 2: c << n, -e, -d; break;
    case 3: c << n, d, -e; break;
    case 4: c << n, -d, e; break;
    case 5: c << d, e, -n; break;
    case 6: c << -d, e, n; break;
    case 7: case 8: case 9: case 10: {
      // Position 7: body (1,1,1)/sqrt 3 along Up (-D): x, y, z at equal angles (54.7 deg) from it, right-handed.
      const double a = std::sqrt(2.0 / 3.0), b = 1.0 / std::sqrt(6.0), h = 1.0 / std::sqrt(2.0), u = 1.0 / std::sqrt(3.0);
      c.col(0) << a, 0.0, -u;
      c.col(1) << -b, -h, -u;
      c.col(2) << -b, h, -u;
      // 8..10: the body turned 180 deg about its z, y, x: the diagonals (-1,-1,1), (-1,1,-1), (1,-1,-1) up.
      static const Eigen::Vector3d flips[] = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
      c = c * flips[position - 7].asDiagonal();
      break;
    }
    default: fail("mount position ", position, " is not one of 1..", kMountPositions, " (Table 2.1's 1..6, body diagonals 7..10)");
  }
  return c;
}

std::string Sampling::validate() const {
  if ((samples > 0) == (rate_hz > 0)) return "sampling: give exactly one of samples (>= 2) or rate_hz (> 0)";
  if (samples == 1) return "sampling: samples must be at least 2";
  return "";
}

std::vector<double> sample_times(double duration_s, const Sampling& sampling) {
  if (auto p = sampling.validate(); !p.empty()) fail(p);
  // A data logger's clock: t_k = k dt for k dt < duration, dt = duration / samples or 1 / rate_hz. (With
  // this convention 1000 samples on 32 rate cycles alias exactly as in the thesis, s4.4.)
  const double dt = sampling.samples > 0 ? duration_s / static_cast<double>(sampling.samples) : 1.0 / sampling.rate_hz;
  const auto n = sampling.samples > 0 ? sampling.samples
                                      : static_cast<std::size_t>(std::ceil(duration_s * sampling.rate_hz - 1e-9));
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = static_cast<double>(k) * dt;
  return t;
}

Excitation excite(const TableProfile& profile, const std::vector<double>& times, const ThermalLagOptions& thermal) {
  if (auto p = profile.check_limits(); !p.empty()) fail(profile.name, ": ", p);
  Excitation ex;
  const std::size_t n = times.size();
  ex.t_s = times;
  ex.latitude_rad = profile.latitude_rad;
  ex.omega_ib_b.resize(n);
  ex.f_b.resize(n);
  ex.chamber_temp_c.resize(n);
  ex.position_id.resize(n);

  const double lat = profile.latitude_rad;
  const Eigen::Vector3d omega_ie_n(earth::kRotationRate * std::cos(lat), 0.0, -earth::kRotationRate * std::sin(lat));
  const Eigen::Vector3d f_n(0.0, 0.0, -earth::normal_gravity(lat));

  // Segment start times and table angles (integral of the table rate), accumulated exactly per segment.
  std::vector<double> start(profile.segments.size() + 1, 0.0), angle(profile.segments.size() + 1, 0.0);
  for (std::size_t i = 0; i < profile.segments.size(); ++i) {
    const auto& s = profile.segments[i];
    start[i + 1] = start[i] + s.duration_s;
    angle[i + 1] = angle[i] + s.rate.integral(s.duration_s, s.duration_s);
  }
  const PiecewiseLinear chamber = profile.chamber_temperature();
  std::size_t seg = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = times[k];
    if (k > 0 && t < times[k - 1]) fail(profile.name, ": sample times must be ascending");
    while (seg + 1 < profile.segments.size() && t >= start[seg + 1]) ++seg;
    const auto& s = profile.segments[seg];
    const double tau = std::clamp(t - start[seg], 0.0, s.duration_s);
    const double rate = s.rate.at(tau, s.duration_s);
    const double alpha = angle[seg] + s.rate.integral(tau, s.duration_s);
    const Eigen::Matrix3d c_t_b = mount_orientation(s.position);
    const Eigen::Matrix3d c_n_b = rotation_z(-alpha) * c_t_b;  // about Down by -alpha = about Up by alpha
    ex.omega_ib_b[k] = c_n_b.transpose() * omega_ie_n + c_t_b.transpose() * Eigen::Vector3d(0, 0, -rate);
    ex.f_b[k] = c_n_b.transpose() * f_n;
    ex.chamber_temp_c[k] = chamber.at(t);
    ex.position_id[k] = s.position;
  }
  ThermalLagOptions options = thermal;
  if (options.tau_s.empty()) options.tau_s = {0.0};
  const ThermalLagResponse lag = thermal_lag_response(options, chamber, times);
  ex.probe_temp_c = lag.stage.front();
  ex.coil_temp_c = lag.stage.back();
  ex.coil_temp_rate_c_per_s = lag.output_rate;
  return ex;
}

}  // namespace gyrosid
