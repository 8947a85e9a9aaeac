#include "sensor/sensor_config.h"

#include <cmath>

#include "core/error.h"
#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {
namespace {

using namespace units;

Polynomial load_polynomial(const ConfigNode& node, const char* coefficients_key, double unit, double argument_unit) {
  // c_i [unit per (argument unit)^i] about reference; stored for an SI argument.
  node.allow_only({"reference_c", coefficients_key});
  Polynomial p;
  p.reference = node.number("reference_c", 0.0);
  p.coefficients = node.numbers(coefficients_key);
  double scale = unit;
  for (double& c : p.coefficients) {
    c *= scale;
    scale /= argument_unit;
  }
  return p;
}

ThermalPath load_thermal(const ConfigNode& node) {
  node.allow_only({"tau_s", "delay_s", "coil_tau_s"});
  ThermalPath t;
  t.tau_s = node.number("tau_s", 0.0);
  t.delay_s = node.number("delay_s", 0.0);
  t.coil_tau_s = node.number("coil_tau_s", 0.0);
  if (auto p = t.validate(); !p.empty()) fail(node.where(), ": ", p);
  return t;
}

NoiseOptions load_noise(const ConfigNode& node) {
  node.allow_only({"arw_deg_rt_h", "white_dph_at_1hz", "bias_instability_dph", "bias_instability_band_s",
                   "bias_instability_per_decade", "rrw_dph_rt_h", "rate_ramp_dph_per_h", "gauss_markov"});
  NoiseOptions n;
  if (node.has("arw_deg_rt_h") && node.has("white_dph_at_1hz")) {
    fail(node.where(), ": give either arw_deg_rt_h or white_dph_at_1hz, not both");
  }
  n.arw_rad_rt_s = deg_rt_h_to_rad_rt_s(node.number("arw_deg_rt_h", 0.0));
  if (node.has("white_dph_at_1hz")) {
    // sigma at 1 Hz equals N in rad/sqrt(s) (sigma = N / sqrt(dt)).
    n.arw_rad_rt_s = dph_to_radps(node.number("white_dph_at_1hz"));
  }
  n.bias_instability_radps = dph_to_radps(node.number("bias_instability_dph", 0.0));
  const auto band = node.numbers("bias_instability_band_s", {0.1, 1e5});
  if (band.size() != 2) fail(node.where("bias_instability_band_s"), ": expected [tau_min_s, tau_max_s]");
  n.bias_instability_tau_min_s = band[0];
  n.bias_instability_tau_max_s = band[1];
  n.bias_instability_per_decade = node.integer("bias_instability_per_decade", 3);
  n.rrw_rad_s_rt_s = dph_rt_h_to_rad_s_rt_s(node.number("rrw_dph_rt_h", 0.0));
  n.rate_ramp_radps2 = dph_per_h_to_radps2(node.number("rate_ramp_dph_per_h", 0.0));
  if (auto gm = node.find("gauss_markov")) {
    for (std::size_t i = 0; i < gm->size(); ++i) {
      const ConfigNode item = gm->at(i);
      item.allow_only({"sigma_dph", "tau_s"});
      n.gauss_markov.push_back({dph_to_radps(item.number("sigma_dph")), item.number("tau_s")});
    }
  }
  if (auto p = n.validate(); !p.empty()) fail(node.where(), ": ", p);
  return n;
}

SplineSurface load_surface(const ConfigNode& node) {
  node.allow_only({"temperatures_c", "rates_dps", "error_ppm", "outside"});
  const auto temps = node.numbers("temperatures_c");
  auto rates = node.numbers("rates_dps");
  const auto rows = node["error_ppm"].as_matrix();
  if (rows.size() != temps.size() || rows.front().size() != rates.size()) {
    fail(node.where("error_ppm"), ": expected ", temps.size(), " rows (temperatures) of ", rates.size(),
         " values (rates), found ", rows.size(), " x ", rows.empty() ? 0 : rows.front().size());
  }
  Eigen::MatrixXd values(static_cast<Eigen::Index>(temps.size()), static_cast<Eigen::Index>(rates.size()));
  for (std::size_t i = 0; i < temps.size(); ++i)
    for (std::size_t j = 0; j < rates.size(); ++j) values(i, j) = ppm_to_ratio(rows[i][j]);
  for (double& r : rates) r = dps_to_radps(r);
  const auto policy = parse_enum<OutsideGridPolicy>(node.text("outside", "error"), node.where("outside"));
  try {
    return SplineSurface(temps, rates, values, policy);
  } catch (const Error& e) {
    fail(node.where(), ": ", e.what());
  }
}

}  // namespace

GyroSensor load_gyro(const ConfigNode& node) {
  node.allow_only({"kind", "name", "description", "bias", "scale_factor", "shupe_dph_per_c_per_min",
                   "g_sensitivity_dph_per_g", "g2_sensitivity_dph_per_g2", "noise", "quantization_arcsec",
                   "range_dps", "thermal"});
  GyroSensor s;
  s.name = node.text("name", "gyro");
  GyroErrorModel& e = s.errors;
  if (auto bias = node.find("bias")) {
    bias->allow_only({"constant_dph", "temperature"});
    e.bias_radps = dph_to_radps(bias->number("constant_dph", 0.0));
    if (auto t = bias->find("temperature")) e.bias_temperature_radps = load_polynomial(*t, "coefficients_dph", dph_to_radps(1.0), 1.0);
  }
  if (auto sf = node.find("scale_factor")) {
    sf->allow_only({"temperature", "rate", "surface", "asymmetry_ppm"});
    if (auto t = sf->find("temperature")) e.scale_factor_temperature = load_polynomial(*t, "coefficients_ppm", 1e-6, 1.0);
    if (auto r = sf->find("rate")) {
      r->allow_only({"coefficients_ppm"});
      // c_j in ppm per (deg/s)^j -> per (rad/s)^j
      Polynomial p;
      p.coefficients = r->numbers("coefficients_ppm");
      double scale = 1e-6;
      for (double& c : p.coefficients) {
        c *= scale;
        scale /= kDegToRad;
      }
      e.scale_factor_rate = p;
    }
    if (auto surface = sf->find("surface")) e.scale_factor_surface = load_surface(*surface);
    e.scale_factor_asymmetry = ppm_to_ratio(sf->number("asymmetry_ppm", 0.0));
  }
  // Shupe: (deg/h) per (deg C/min) -> (rad/s) per (deg C/s)
  e.shupe_rad_per_c = dph_to_radps(node.number("shupe_dph_per_c_per_min", 0.0)) * kSecondsPerMinute;
  if (node.has("g_sensitivity_dph_per_g")) {
    const auto g = node.numbers("g_sensitivity_dph_per_g");
    if (g.size() != 3) fail(node.where("g_sensitivity_dph_per_g"), ": expected [x, y, z]");
    e.g_sensitivity = Eigen::Vector3d(g[0], g[1], g[2]) * dph_to_radps(1.0) / kStandardGravity;
  }
  if (node.has("g2_sensitivity_dph_per_g2")) {
    const auto rows = node["g2_sensitivity_dph_per_g2"].as_matrix();
    if (rows.size() != 3 || rows[0].size() != 3) fail(node.where("g2_sensitivity_dph_per_g2"), ": expected a 3 x 3 matrix");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        e.g2_sensitivity(i, j) = rows[i][j] * dph_to_radps(1.0) / (kStandardGravity * kStandardGravity);
    if (!e.g2_sensitivity.isApprox(e.g2_sensitivity.transpose(), 1e-12)) {
      fail(node.where("g2_sensitivity_dph_per_g2"), ": the matrix must be symmetric");
    }
  }
  if (auto noise = node.find("noise")) s.noise = load_noise(*noise);
  s.quantization_rad = node.number("quantization_arcsec", 0.0) * kArcsecToRad;
  if (node.has("range_dps")) s.range_radps = dps_to_radps(node.number("range_dps"));
  if (auto thermal = node.find("thermal")) s.thermal = load_thermal(*thermal);
  if (auto p = s.validate(); !p.empty()) fail(node.where(), ": ", p);
  return s;
}

TriadSensor load_triad(const ConfigNode& node) {
  node.allow_only({"kind", "name", "description", "gyro", "gyros", "misalignment_mrad", "thermal"});
  TriadSensor t;
  t.name = node.text("name", "triad");
  if (node.has("gyro") == node.has("gyros")) {
    fail(node.where(), ": a triad needs either 'gyro' (one file for all three axes) or 'gyros' {x, y, z}");
  }
  for (int i = 0; i < 3; ++i) {
    const std::string file = node.has("gyro") ? node.text("gyro") : node["gyros"].text(kTriadAxes[i]);
    const ConfigNode gyro_node = ConfigNode::load(node.resolve(file));
    if (gyro_node.text("kind", "gyro") != "gyro") fail(gyro_node.where("kind"), ": a triad axis must be kind: gyro");
    t.gyros[i] = load_gyro(gyro_node);
  }
  if (auto m = node.find("misalignment_mrad")) {
    m->allow_only({"x", "y", "z"});
    for (int i = 0; i < 3; ++i) {
      if (auto axis = m->find(kTriadAxes[i])) {
        axis->allow_only({"ia", "insertion"});
        const auto ia = axis->numbers("ia", {0.0, 0.0});
        const auto ins = axis->numbers("insertion", {0.0, 0.0});
        if (ia.size() != 2 || ins.size() != 2) fail(axis->where(), ": expected ia: [x, y] and insertion: [x, y]");
        t.alignment[i] = {ia[0] * 1e-3, ia[1] * 1e-3, ins[0] * 1e-3, ins[1] * 1e-3};
      }
    }
  }
  if (auto thermal = node.find("thermal")) t.thermal = load_thermal(*thermal);
  if (auto p = t.validate(); !p.empty()) fail(node.where(), ": ", p);
  return t;
}

SensorSpec load_sensor(const ConfigNode& node) {
  const std::string kind = node.text("kind", "gyro");
  if (kind == "gyro") return load_gyro(node);
  if (kind == "triad") return load_triad(node);
  fail(node.where("kind"), ": unknown sensor kind '", kind, "'; known: gyro, triad");
}

SensorSpec load_sensor_file(const std::string& path) { return load_sensor(ConfigNode::load(path)); }

const ThermalPath& thermal_path(const SensorSpec& spec) {
  return std::visit([](const auto& s) -> const ThermalPath& { return s.thermal; }, spec);
}

TriadSensor as_triad(const SensorSpec& spec) {
  if (const auto* t = std::get_if<TriadSensor>(&spec)) return *t;
  const auto& g = std::get<GyroSensor>(spec);
  TriadSensor t;
  t.name = g.name + " (x3)";
  t.gyros = {g, g, g};
  t.thermal = g.thermal;
  return t;
}

SensorSpec with_gyro_noise(SensorSpec spec, const NoiseOptions& noise) {
  if (auto* g = std::get_if<GyroSensor>(&spec)) g->noise = noise;
  if (auto* t = std::get_if<TriadSensor>(&spec))
    for (auto& g : t->gyros) g.noise = noise;
  return spec;
}

const std::string& sensor_name(const SensorSpec& spec) {
  return std::visit([](const auto& s) -> const std::string& { return s.name; }, spec);
}

}  // namespace gyrosid
