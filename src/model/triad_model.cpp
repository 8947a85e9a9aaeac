#include "model/triad_model.h"

#include <Eigen/LU>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {
namespace {

Eigen::MatrixX3d columns(const Recording& rec, const std::string& prefix, const std::string& suffix, double scale) {
  Eigen::MatrixX3d m(static_cast<Eigen::Index>(rec.rows()), 3);
  for (int a = 0; a < 3; ++a) {
    const auto& c = rec.column(prefix + kTriadAxes[a] + suffix);
    for (std::size_t k = 0; k < c.size(); ++k) m(static_cast<Eigen::Index>(k), a) = c[k] * scale;
  }
  return m;
}

// Row-major 3x3 <-> JSON, null entries where `known` is false.
nlohmann::json matrix_json(const Eigen::Matrix3d& m, const std::array<std::array<bool, 3>, 3>* known, double scale = 1.0) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < 3; ++j) {
      if (known && !(*known)[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]) row.push_back(nullptr);
      else row.push_back(m(i, j) * scale);
    }
    rows.push_back(row);
  }
  return rows;
}

Eigen::Matrix3d matrix_from_json(const nlohmann::json& j, const std::string& where, double scale = 1.0) {
  if (!j.is_array() || j.size() != 3) fail(where, ": expected a 3 x 3 matrix (three rows)");
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    const auto& row = j[static_cast<std::size_t>(i)];
    if (!row.is_array() || row.size() != 3) fail(where, ": row ", i + 1, " does not have three entries");
    for (int k = 0; k < 3; ++k) {
      const auto& v = row[static_cast<std::size_t>(k)];
      m(i, k) = v.is_null() ? 0.0 : v.get<double>() * scale;  // null: not determined, nominal 0
    }
  }
  return m;
}

}  // namespace

TriadData make_triad_data(const Recording& rec) {
  if (rec.kind() != RecordingKind::triad) {
    fail(rec.source(), ": a triad model needs a triad recording (gyro_{x,y,z}_dps, ref_rate_{x,y,z}_dps); this is a single-gyro recording");
  }
  TriadData d;
  d.t_s = rec.column("t_s");
  d.gyro = columns(rec, "gyro_", "_dps", units::kDegToRad);
  d.reference = columns(rec, "ref_rate_", "_dps", units::kDegToRad);
  if (rec.has("temp_x_c")) {
    d.temp_c = columns(rec, "temp_", "_c", 1.0);
  } else {
    const auto& t = rec.column("temp_c");
    d.temp_c.resize(static_cast<Eigen::Index>(t.size()), 3);
    for (std::size_t k = 0; k < t.size(); ++k) d.temp_c.row(static_cast<Eigen::Index>(k)).setConstant(t[k]);
  }
  if (rec.has("accel_x_mps2") && rec.has("accel_y_mps2") && rec.has("accel_z_mps2")) d.accel = columns(rec, "accel_", "_mps2", 1.0);
  if (rec.has("position_id")) {
    for (double p : rec.column("position_id")) d.position_id.push_back(static_cast<int>(std::lround(p)));
  }
  return d;
}

Recording axis_recording(const TriadData& d, int axis, const Eigen::VectorXd* error) {
  Recording rec(str_cat("<triad gyro ", kTriadAxes[axis], ">"));
  const auto n = static_cast<std::size_t>(d.size());
  std::vector<double> gyro(n), temp(n), ref(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    gyro[k] = units::radps_to_dps(d.gyro(row, axis));
    temp[k] = d.temp_c(row, axis);
    ref[k] = error ? units::radps_to_dps(d.gyro(row, axis) - (*error)(row)) : std::numeric_limits<double>::quiet_NaN();
  }
  rec.set_column("t_s", d.t_s);
  rec.set_column("gyro_dps", std::move(gyro));
  rec.set_column("temp_c", std::move(temp));
  if (error) rec.set_column("ref_rate_dps", std::move(ref));
  return rec;
}

double TriadBias::at(int axis, double temp_c) const {
  const Eigen::VectorXd& c = coefficients[static_cast<std::size_t>(axis)];
  const double v = normalised(temp_c);
  double out = 0.0;
  for (Eigen::Index k = c.size(); k-- > 0;) out = out * v + c(k);
  return out;
}

Eigen::MatrixX3d TriadModel::surface_errors(const TriadData& data) const {
  Eigen::MatrixX3d e = Eigen::MatrixX3d::Zero(data.size(), 3);
  for (int a = 0; a < 3; ++a) {
    const auto& s = surfaces[static_cast<std::size_t>(a)];
    if (!s) continue;
    if (s->target() != ModelTarget::error) fail("triad model: the surface of gyro ", kTriadAxes[a], " must model the rate error (target error)");
    e.col(a) = s->predict(make_dataset(axis_recording(data, a), s->features(), ModelTarget::error));
  }
  return e;
}

Eigen::MatrixX3d TriadModel::offsets(const TriadData& data) const {
  Eigen::MatrixX3d out = surface_errors(data);
  for (Eigen::Index k = 0; k < data.size(); ++k) {
    for (int a = 0; a < 3; ++a) out(k, a) += bias.at(a, data.temp_c(k, a));
  }
  if (g_sensitivity) {
    if (!data.has_accel()) fail("triad model: the model has a g-sensitivity but the data have no accel_{x,y,z}_mps2 columns");
    out += data.accel * g_sensitivity->transpose();
  }
  return out;
}

Eigen::MatrixX3d TriadModel::compensate(const TriadData& data) const {
  const Eigen::Matrix3d inverse = (Eigen::Matrix3d::Identity() + misalignment).inverse();
  return (data.gyro - offsets(data)) * inverse.transpose();
}

Eigen::MatrixX3d TriadModel::predict_outputs(const TriadData& data) const {
  return data.reference * (Eigen::Matrix3d::Identity() + misalignment).transpose() + offsets(data);
}

nlohmann::json triad_model_json(const TriadModel& m, const std::array<std::array<bool, 3>, 3>* known) {
  nlohmann::json coefficients = nlohmann::json::array();
  for (const auto& c : m.bias.coefficients) {
    std::vector<double> dph(static_cast<std::size_t>(c.size()));
    for (Eigen::Index k = 0; k < c.size(); ++k) dph[static_cast<std::size_t>(k)] = units::radps_to_dph(c(k));
    coefficients.push_back(dph);
  }
  nlohmann::json surfaces = nlohmann::json::object();
  for (int a = 0; a < 3; ++a) {
    const auto& s = m.surfaces[static_cast<std::size_t>(a)];
    surfaces[kTriadAxes[a]] = s ? s->to_json() : nlohmann::json(nullptr);
  }
  return {{"format", kModelFormat},
          {"kind", kTriadModelKind},
          {"misalignment", {{"matrix", matrix_json(m.misalignment, known)}}},
          {"bias", {{"reference_temperature_c", m.bias.reference_c},
                    {"temperature_scale_c", m.bias.scale_c},
                    {"coefficients_dph", coefficients}}},
          {"g_sensitivity_dph_per_mps2", m.g_sensitivity ? matrix_json(*m.g_sensitivity, nullptr, units::radps_to_dph(1.0)) : nlohmann::json(nullptr)},
          {"surfaces", surfaces}};
}

TriadModel triad_model_from_json(const nlohmann::json& j, const std::string& source) {
  try {
    if (j.value("format", "") != kModelFormat || j.value("kind", "") != kTriadModelKind) {
      fail(source, ": not a gyrosid triad model (expected \"format\": \"", kModelFormat, "\", \"kind\": \"triad\")");
    }
    TriadModel m;
    m.misalignment = matrix_from_json(j.at("misalignment").at("matrix"), source + ": misalignment.matrix");
    const auto& b = j.at("bias");
    m.bias.reference_c = b.at("reference_temperature_c").get<double>();
    m.bias.scale_c = b.at("temperature_scale_c").get<double>();
    if (!(m.bias.scale_c > 0)) fail(source, ": bias.temperature_scale_c must be positive");
    const auto& c = b.at("coefficients_dph");
    if (!c.is_array() || c.size() != 3) fail(source, ": bias.coefficients_dph must hold one list per gyro (x, y, z)");
    for (int a = 0; a < 3; ++a) {
      const auto v = c[static_cast<std::size_t>(a)].get<std::vector<double>>();
      if (v.empty()) fail(source, ": bias.coefficients_dph of gyro ", kTriadAxes[a], " is empty");
      Eigen::VectorXd& out = m.bias.coefficients[static_cast<std::size_t>(a)];
      out.resize(static_cast<Eigen::Index>(v.size()));
      for (std::size_t k = 0; k < v.size(); ++k) out(static_cast<Eigen::Index>(k)) = units::dph_to_radps(v[k]);
    }
    if (j.contains("g_sensitivity_dph_per_mps2") && !j["g_sensitivity_dph_per_mps2"].is_null()) {
      m.g_sensitivity = matrix_from_json(j["g_sensitivity_dph_per_mps2"], source + ": g_sensitivity_dph_per_mps2", units::dph_to_radps(1.0));
    }
    const auto& s = j.at("surfaces");
    for (int a = 0; a < 3; ++a) {
      const auto& sj = s.at(kTriadAxes[a]);
      if (sj.is_null()) continue;
      std::shared_ptr<const CalibrationModel> surface = model_from_json(sj, str_cat(source, ": surfaces.", kTriadAxes[a]));
      if (surface->target() != ModelTarget::error) fail(source, ": surfaces.", kTriadAxes[a], " must model the rate error (target error)");
      m.surfaces[static_cast<std::size_t>(a)] = std::move(surface);
    }
    return m;
  } catch (const nlohmann::json::exception& e) {
    fail(source, ": malformed triad model: ", e.what());
  }
}

nlohmann::json TriadModel::to_json() const { return triad_model_json(*this); }

}  // namespace gyrosid
