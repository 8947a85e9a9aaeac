// A triad model for other stacks:
//
//   C99      <prefix>.h / <prefix>.c, dependency-free:
//              void <prefix>_compensate(const double gyro_radps[3], const double temp_c[3],
//                                       const double f_mps2[3], double omega_radps[3]);
//            omega = (I + M)^-1 (g - b(T) - G f - e(T, g)), the inverse computed at export; each surface is
//            exported by its own model (CalibrationModel::export_c_body) as <prefix>_<axis>_predict.
//   Kalibr   the IMU YAML of Kalibr's "scale-misalignment" model (kalibr_calibrate_imu_camera output):
//              omega_meas = M_k C_gyro_i omega_i + A C_gyro_i a_i + b,   M_k lower triangular, C_gyro_i a rotation,
//            so (I + M) = M_k C_gyro_i (an RQ factorisation) and A = G C_gyro_i^T. Noise density from the fit,
//            units in comments; what Kalibr's model cannot hold (b(T), the surfaces) is listed as comments.
#pragma once

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <string>

#include "model/triad_model.h"

namespace gyrosid {

void export_triad_c(const TriadModel& model, const std::filesystem::path& dir, const std::string& prefix);

struct KalibrImu {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();         // lower triangular, positive diagonal
  Eigen::Matrix3d c_gyro_i = Eigen::Matrix3d::Identity();  // rotation
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();             // rad/s per m/s^2
};
// (I + M) = m c_gyro_i, A = G c_gyro_i^T.
KalibrImu kalibr_intrinsics(const TriadModel& model);

struct KalibrExportInfo {
  std::array<double, 3> noise_density{};  // rad/s/sqrt(Hz); NaN or 0: unknown
  double update_rate_hz = 0.0;
  std::string rostopic = "/imu0";
  std::string source;                     // the model file, for the header comment
};
std::string kalibr_imu_yaml(const TriadModel& model, const KalibrExportInfo& info);

}  // namespace gyrosid
