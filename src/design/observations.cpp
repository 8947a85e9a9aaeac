#include "design/observations.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace gyrosid::design {

Observations observe(const TableProfile& profile, const std::vector<double>& times, const std::vector<double>& weights_s,
                     const GyroSensor& gyro, const ThermalPath& thermal, const RateRelaxation* relaxation) {
  if (times.size() != weights_s.size()) fail("observe: ", times.size(), " times for ", weights_s.size(), " weights");
  Excitation ex = excite(profile, times, thermal.lag_options());
  std::vector<double> weights = weights_s;
  if (relaxation) {
    // Replace the table rate at each time by the rate nodes: the input axis sees s * table rate, s = +-1 in
    // positions 1 and 2 (axis along the table's), 0 in the others (where the table only turns Earth rate).
    if (relaxation->rate_nodes_radps.size() != times.size()) fail("observe: rate relaxation needs nodes per time");
    Excitation relaxed = ex;
    for (auto* v : {&relaxed.t_s, &relaxed.chamber_temp_c, &relaxed.probe_temp_c, &relaxed.coil_temp_c, &relaxed.coil_temp_rate_c_per_s}) v->clear();
    relaxed.omega_ib_b.clear(), relaxed.f_b.clear(), relaxed.position_id.clear(), weights.clear();
    std::size_t seg = 0;
    double seg_start = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      while (seg + 1 < profile.segments.size() && times[k] >= seg_start + profile.segments[seg].duration_s) {
        seg_start += profile.segments[seg++].duration_s;
      }
      const ProfileSegment& s = profile.segments[seg];
      const double along = -mount_orientation(s.position).row(2).z();  // table rate is about -Down
      const double table = s.rate.at(times[k] - seg_start, s.duration_s);
      const auto& nodes = relaxation->rate_nodes_radps[k];
      for (std::size_t j = 0; j < nodes.size(); ++j) {
        relaxed.t_s.push_back(times[k]);
        Eigen::Vector3d w = ex.omega_ib_b[k];
        w.z() += along * (nodes[j] - table);
        relaxed.omega_ib_b.push_back(w);
        relaxed.f_b.push_back(ex.f_b[k]);
        relaxed.chamber_temp_c.push_back(ex.chamber_temp_c[k]);
        relaxed.probe_temp_c.push_back(ex.probe_temp_c[k]);
        relaxed.coil_temp_c.push_back(ex.coil_temp_c[k]);
        relaxed.coil_temp_rate_c_per_s.push_back(ex.coil_temp_rate_c_per_s[k]);
        relaxed.position_id.push_back(ex.position_id[k]);
        weights.push_back(weights_s[k] * relaxation->weights[j]);
      }
    }
    ex = std::move(relaxed);
  }
  GyroSensor quiet = gyro;
  quiet.noise = NoiseOptions{};
  quiet.quantization_rad = 0.0;
  const GyroOutput out = simulate_single(quiet, ex, 0);
  const auto n = static_cast<Eigen::Index>(ex.size());
  Observations o;
  o.inputs.t_s = ex.t_s;
  o.inputs.rate = Eigen::Map<const Eigen::VectorXd>(out.rate_radps.data(), n);
  o.inputs.temp_c = Eigen::Map<const Eigen::VectorXd>(ex.probe_temp_c.data(), n);
  o.true_error.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) o.true_error(i) = o.inputs.rate(i) - ex.omega_ib_b[static_cast<std::size_t>(i)].z();
  o.weight_s = Eigen::Map<const Eigen::VectorXd>(weights.data(), n);
  return o;
}

Quadrature programme_quadrature(const TableProfile& profile, double max_spacing_s, int points_per_cycle) {
  constexpr double kGoldenFraction = 0.6180339887498949;  // (sqrt 5 - 1) / 2: phases that never repeat
  if (!(max_spacing_s > 0) || points_per_cycle < 1) fail("programme quadrature: spacing and points per cycle must be positive");
  Quadrature q;
  double start = 0.0;
  for (const auto& s : profile.segments) {
    double count = std::ceil(s.duration_s / max_spacing_s);
    if (s.rate.shape == RateProfile::Shape::triangle) count = std::max(count, std::ceil(s.rate.cycles * points_per_cycle));
    const auto n = static_cast<std::size_t>(std::max(1.0, count));
    const double h = s.duration_s / static_cast<double>(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double offset = std::fmod(0.5 + kGoldenFraction * static_cast<double>(k), 1.0);
      q.times.push_back(start + (static_cast<double>(k) + offset) * h);
      q.weights_s.push_back(h);
    }
    start += s.duration_s;
  }
  return q;
}

Quadrature sample_quadrature(const std::vector<double>& t, double duration_s) {
  Quadrature q{t, std::vector<double>(t.size())};
  // Each sample stands for the interval up to the next one (the last for the rest of the trajectory).
  for (std::size_t k = 0; k < t.size(); ++k) q.weights_s[k] = (k + 1 < t.size() ? t[k + 1] : std::max(duration_s, t[k] + 1e-9)) - t[k];
  return q;
}

}  // namespace gyrosid::design
