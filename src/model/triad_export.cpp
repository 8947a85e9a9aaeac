#include "model/triad_export.h"

#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/triad_axes.h"
#include "core/units.h"

namespace gyrosid {
namespace {

std::string hex(double v) {
  std::ostringstream s;
  s << std::hexfloat << v;
  return s.str();
}

std::string c_matrix(const std::string& name, const Eigen::Matrix3d& m) {
  std::ostringstream s;
  s << "static const double " << name << "[3][3] = {";
  for (int i = 0; i < 3; ++i) s << (i ? ", " : "") << "{" << hex(m(i, 0)) << ", " << hex(m(i, 1)) << ", " << hex(m(i, 2)) << "}";
  s << "};\n";
  return s.str();
}

void check_identifier(const std::string& prefix) {
  bool ok = !prefix.empty() && !std::isdigit(static_cast<unsigned char>(prefix.front()));
  for (char c : prefix) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!ok) fail("C export: prefix '", prefix, "' is not a C identifier");
}

std::string yaml_matrix(const std::string& indent, const Eigen::Matrix3d& m) {
  std::ostringstream s;
  s << std::setprecision(17);
  for (int i = 0; i < 3; ++i) s << indent << "- [" << m(i, 0) + 0.0 << ", " << m(i, 1) + 0.0 << ", " << m(i, 2) + 0.0 << "]\n";  // + 0.0: no -0
  return s.str();
}

}  // namespace

void TriadModel::export_c(const std::filesystem::path& dir, const std::string& prefix) const { export_triad_c(*this, dir, prefix); }

void export_triad_c(const TriadModel& model, const std::filesystem::path& dir, const std::string& prefix) {
  check_identifier(prefix);
  std::ostringstream h, c;
  std::string guard = prefix;
  for (char& ch : guard) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  h << "/* " << prefix << ".h - gyrosid triad calibration, generated; dependency-free C99. */\n"
    << "#ifndef " << guard << "_H\n#define " << guard << "_H\n\n"
    << "/* Compensated body rates (rad/s) from the three gyro outputs (rad/s), each gyro's temperature (deg C)\n"
    << "   and the specific force in body axes (m/s^2; ignored without g-sensitivity):\n"
    << "   omega = (I + M)^-1 (g - b(T) - G f - e(T, g)). */\n"
    << "void " << prefix << "_compensate(const double gyro_radps[3], const double temp_c[3], const double f_mps2[3],\n"
    << "    double omega_radps[3]);\n\n#endif\n";
  c << "/* " << prefix << ".c - gyrosid triad calibration, generated. */\n#include <math.h>\n#include \"" << prefix << ".h\"\n\n";
  const Eigen::Matrix3d inverse = (Eigen::Matrix3d::Identity() + model.misalignment).inverse();
  c << "/* (I + M)^-1, M the misalignment / scale-factor matrix (thesis eq 3.72). */\n" << c_matrix(prefix + "_inverse", inverse);
  c << "/* G, rad/s per m/s^2. */\n" << c_matrix(prefix + "_g", model.g_sensitivity.value_or(Eigen::Matrix3d::Zero()));
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd& b = model.bias.coefficients[static_cast<std::size_t>(a)];
    c << "static const double " << prefix << "_bias_" << kTriadAxes[a] << "[" << b.size() << "] = {";
    for (Eigen::Index k = 0; k < b.size(); ++k) c << (k ? ", " : "") << hex(b(k));
    c << "};\n";
  }
  std::string surface_calls;
  for (int a = 0; a < 3; ++a) {
    const auto& s = model.surfaces[static_cast<std::size_t>(a)];
    if (!s) continue;
    if (s->features() != default_features()) fail("C export: the surface of gyro ", kTriadAxes[a], " takes inputs other than measured_rate, temperature");
    CExport e;
    e.prefix = prefix + "_" + kTriadAxes[a];
    s->export_c_body(e);
    c << "\n/* Surface of gyro " << kTriadAxes[a] << " (" << s->kind() << "), rate error in rad/s. */\n" << e.source.str();
    surface_calls += str_cat("  x[0] = gyro_radps[", a, "]; x[1] = temp_c[", a, "]; r[", a, "] -= ", e.prefix, "_predict(x);\n");
  }
  c << "\nstatic double " << prefix << "_poly(const double* c, int n, double v) {\n  double s = 0.0;\n  int i;\n"
    << "  for (i = n - 1; i >= 0; --i) s = s * v + c[i];\n  return s;\n}\n\n"
    << "void " << prefix << "_compensate(const double gyro_radps[3], const double temp_c[3], const double f_mps2[3],\n"
    << "    double omega_radps[3]) {\n  double r[3], x[2];\n  int i;\n  (void)x;\n"
    << "  r[0] = gyro_radps[0] - " << prefix << "_poly(" << prefix << "_bias_x, " << model.bias.coefficients[0].size() << ", (temp_c[0] - " << hex(model.bias.reference_c) << ") / " << hex(model.bias.scale_c) << ");\n"
    << "  r[1] = gyro_radps[1] - " << prefix << "_poly(" << prefix << "_bias_y, " << model.bias.coefficients[1].size() << ", (temp_c[1] - " << hex(model.bias.reference_c) << ") / " << hex(model.bias.scale_c) << ");\n"
    << "  r[2] = gyro_radps[2] - " << prefix << "_poly(" << prefix << "_bias_z, " << model.bias.coefficients[2].size() << ", (temp_c[2] - " << hex(model.bias.reference_c) << ") / " << hex(model.bias.scale_c) << ");\n"
    << "  for (i = 0; i < 3; ++i) r[i] -= " << prefix << "_g[i][0] * f_mps2[0] + " << prefix << "_g[i][1] * f_mps2[1] + " << prefix << "_g[i][2] * f_mps2[2];\n"
    << surface_calls
    << "  for (i = 0; i < 3; ++i) omega_radps[i] = " << prefix << "_inverse[i][0] * r[0] + " << prefix << "_inverse[i][1] * r[1] + " << prefix << "_inverse[i][2] * r[2];\n}\n";
  write_file_atomic(dir / (prefix + ".h"), h.str());
  write_file_atomic(dir / (prefix + ".c"), c.str());
}

KalibrImu kalibr_intrinsics(const TriadModel& model) {
  // (I + M)^T = Q R (Householder QR)  =>  (I + M) = R^T Q^T: lower triangular times a rotation.
  const Eigen::Matrix3d k = Eigen::Matrix3d::Identity() + model.misalignment;
  const Eigen::HouseholderQR<Eigen::Matrix3d> qr(k.transpose());
  Eigen::Matrix3d q = qr.householderQ();
  Eigen::Matrix3d r = qr.matrixQR().triangularView<Eigen::Upper>();
  // Make R's diagonal positive (R = D D R, Q = Q D with D = diag(sign)); then det Q = sign(det K) = +1.
  const Eigen::Vector3d sign = r.diagonal().cwiseSign();
  q = q * sign.asDiagonal();
  r = sign.asDiagonal() * r;
  if (q.determinant() < 0) fail("Kalibr export: det(I + M) <= 0 - not a small misalignment");
  KalibrImu out;
  out.m = r.transpose();
  out.c_gyro_i = q.transpose();
  out.a = model.g_sensitivity.value_or(Eigen::Matrix3d::Zero()) * out.c_gyro_i.transpose();
  return out;
}

std::string kalibr_imu_yaml(const TriadModel& model, const KalibrExportInfo& info) {
  const KalibrImu k = kalibr_intrinsics(model);
  double density = 0.0;
  for (double n : info.noise_density) density = std::max(density, std::isfinite(n) ? n : 0.0);
  std::ostringstream y;
  y << std::setprecision(17);
  y << "# Kalibr IMU configuration, model scale-misalignment - written by gyrosid export --format kalibr"
    << (info.source.empty() ? "" : " from " + info.source) << "\n"
    << "# Gyroscope model (Kalibr): omega_meas = M C_gyro_i omega_i + A C_gyro_i a_i + b, with M lower triangular\n"
    << "# (scale and non-orthogonality), C_gyro_i a rotation (gyro axes from IMU axes), A the g-sensitivity.\n"
    << "# gyrosid's (I + M_gyrosid) = M C_gyro_i and G = A C_gyro_i: the same matrix, factorised.\n"
    << "imu0:\n"
    << "  T_i_b:  # IMU frame = body frame of the calibration (4x4 homogeneous, dimensionless / m)\n"
    << "    - [1.0, 0.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0, 0.0]\n    - [0.0, 0.0, 1.0, 0.0]\n    - [0.0, 0.0, 0.0, 1.0]\n"
    << "  gyroscope_noise_density: " << density << "  # [rad/s/sqrt(Hz)] white noise (angle random walk), largest of the three gyros\n"
    << "  gyroscope_random_walk: 0.0  # [rad/s^2/sqrt(Hz)] not estimated by gyrosid's triad fit - set it from an Allan deviation\n"
    << "  accelerometer_noise_density: 0.0  # [m/s^2/sqrt(Hz)] not estimated (gyro calibration only)\n"
    << "  accelerometer_random_walk: 0.0  # [m/s^3/sqrt(Hz)] not estimated\n"
    << "  model: scale-misalignment\n"
    << "  rostopic: " << info.rostopic << "\n"
    << "  time_offset: 0.0  # [s]\n"
    << "  update_rate: " << info.update_rate_hz << "  # [Hz]\n"
    << "  gyroscopes:\n"
    << "    M:  # dimensionless, lower triangular\n" << yaml_matrix("      ", k.m)
    << "    C_gyro_i:  # rotation, dimensionless\n" << yaml_matrix("      ", k.c_gyro_i)
    << "    A:  # [(rad/s)/(m/s^2)]\n" << yaml_matrix("      ", k.a)
    << "  accelerometers:\n"
    << "    M:  # dimensionless; identity: the accelerometers were not calibrated here\n" << yaml_matrix("      ", Eigen::Matrix3d::Identity());
  y << "# Not representable in Kalibr's model (apply them before Kalibr's, or use the C99 export):\n";
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd& c = model.bias.coefficients[static_cast<std::size_t>(a)];
    y << "#   gyro " << kTriadAxes[a] << " bias b(T) = sum_k c_k ((T - " << model.bias.reference_c << " C) / " << model.bias.scale_c << " C)^k, c [deg/h] = [";
    for (Eigen::Index i = 0; i < c.size(); ++i) y << (i ? ", " : "") << units::radps_to_dph(c(i));
    y << "]" << (model.surfaces[static_cast<std::size_t>(a)] ? str_cat("; error surface e(T, g): ", model.surfaces[static_cast<std::size_t>(a)]->kind(), " model") : "") << "\n";
  }
  return y.str();
}

}  // namespace gyrosid
