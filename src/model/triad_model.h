// The calibration model of a gyro triad - the misalignment chain of thesis s3.4 (eq 3.72) together with each
// gyro's own error model (eq 3.48):
//
//   g = (I + M) omega_ib_b + b(T) + G f_b + e(T, g) + noise
//
//   g          the three gyro outputs, rad/s (recording columns gyro_{x,y,z}_dps)
//   omega_ib_b the body rate w.r.t. inertial space, body axes, Earth rate included (ref_rate_{x,y,z}_dps)
//   M          the combined misalignment / scale-factor matrix, row i = gyro i: M_ii its scale-factor error
//              (dimensionless), M_ij (i != j) the small angle (rad) by which its input axis leans towards body
//              axis j - to first order the sums of its IA->RA and insertion angles (eq 3.72, misalignment.h)
//   b_i(T)     gyro i's bias, a polynomial in v = (T_i - T_0) / T_s of its temperature, rad/s
//   G          g-sensitivity, rad/s per m/s^2 of specific force in body axes (optional)
//   e_i(T, g)  gyro i's remaining error surface over its own measured rate and temperature: any single-gyro
//              CalibrationModel of target "error" (classical, grey-box, RBF); none when not modelled
//
// The surfaces take the measured rate (as every single-gyro model does), so compensation is explicit and
// inverts (I + M) exactly (not by its first-order transpose, see misalignment.h):
//
//   omega = (I + M)^-1 (g - b(T) - G f - e(T, g))
//
// An entry the calibration could not determine (observability) is held at its nominal value 0 and marked
// unknown; compensation uses the nominal value.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/recording.h"
#include "model/calibration_model.h"
#include "model/sensor_model.h"

namespace gyrosid {

// A triad recording's samples in SI (RECORDING_FORMAT.md, gyro triad).
struct TriadData {
  std::vector<double> t_s;
  Eigen::MatrixX3d gyro;       // N x 3, rad/s
  Eigen::MatrixX3d temp_c;     // N x 3, each gyro's temperature (temp_{x,y,z}_c, or temp_c on all three)
  Eigen::MatrixX3d reference;  // N x 3, body rate rad/s; NaN where not recorded
  Eigen::MatrixX3d accel;      // N x 3, specific force m/s^2, body axes; 0 rows when not recorded
  std::vector<int> position_id;  // empty when not recorded

  Eigen::Index size() const { return gyro.rows(); }
  bool has_reference() const { return reference.rows() == gyro.rows() && reference.allFinite(); }
  bool has_accel() const { return accel.rows() == gyro.rows() && gyro.rows() > 0; }
};

// Reads the triad columns; errors name the recording and the missing column (a single-gyro recording is
// refused with the reason).
TriadData make_triad_data(const Recording& recording);

// Gyro `axis` of a triad as a single-gyro recording (t_s, gyro_dps, temp_c, ref_rate_dps): the input of its
// surface. `error` (rad/s, optional) is the error the surface should learn; ref_rate_dps = gyro - error, so
// that a single-gyro model fitted to it learns exactly that error.
Recording axis_recording(const TriadData& data, int axis, const Eigen::VectorXd* error = nullptr);

// b_i(T) = sum_k c_ik v^k, v = (T - reference_c) / scale_c; coefficients rad/s, one vector per gyro.
struct TriadBias {
  double reference_c = 25.0;
  double scale_c = 1.0;
  std::array<Eigen::VectorXd, 3> coefficients{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1)};
  double at(int axis, double temp_c) const;
  double normalised(double temp_c) const { return (temp_c - reference_c) / scale_c; }
};

inline constexpr std::string_view kTriadModelKind = "triad";

class TriadModel : public SensorModel {
 public:
  Eigen::Matrix3d misalignment = Eigen::Matrix3d::Zero();           // M
  TriadBias bias;                                                   // b(T)
  std::optional<Eigen::Matrix3d> g_sensitivity;                     // G, rad/s per m/s^2
  std::array<std::shared_ptr<const CalibrationModel>, 3> surfaces;  // e_i; null: none

  // e_i(T_i, g_i) of every sample (zero for an axis without surface), N x 3 rad/s.
  Eigen::MatrixX3d surface_errors(const TriadData& data) const;
  // b(T) + G f + e(T, g) of every sample: everything but (I + M) omega. N x 3 rad/s.
  Eigen::MatrixX3d offsets(const TriadData& data) const;
  // The compensated body rates, N x 3 rad/s.
  Eigen::MatrixX3d compensate(const TriadData& data) const;
  // The modelled outputs for the recorded reference rates: (I + M) omega + offsets. N x 3 rad/s.
  Eigen::MatrixX3d predict_outputs(const TriadData& data) const;

  std::string_view kind() const final { return kTriadModelKind; }
  int gyros() const final { return 3; }
  nlohmann::json to_json() const final;  // triad_model_json(*this)
  // <prefix>_compensate of three gyros (triad_export.h export_triad_c).
  void export_c(const std::filesystem::path& dir, const std::string& prefix) const final;
  // The recording with compensated_{x,y,z}_dps, the body rates (compensate_recording.cpp); the file's version
  // refuses an axis.
  CompensatedRecording compensate_recording(Recording recording) const final;
  CompensatedRecording compensate_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                       const std::string& axis) const final;
};

// The model's values in a model file (format gyrosid-model/1, kind "triad"): misalignment.matrix (null
// entries: not determined, held at 0), bias (polynomial, deg/h), g_sensitivity_dph_per_mps2, surfaces.
// Fit results (sigmas, observability, summary) are added beside them by the writer of the fit.
nlohmann::json triad_model_json(const TriadModel& model, const std::array<std::array<bool, 3>, 3>* known = nullptr);
// The triad entry of model_kinds() reads it (load_sensor_model, sensor_model.h); Errors name the source.
TriadModel triad_model_from_json(const nlohmann::json& j, const std::string& source);

}  // namespace gyrosid
