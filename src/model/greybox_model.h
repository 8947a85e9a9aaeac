// Grey-box calibration model: the unified sensor model of src/sensor (thesis eq 3.48) with its coefficients
// estimated from a recording - the "simulation" the missing-physics finder compares recordings against.
//
//   w_meas = w + dSF(T_c, w) w + b(T_c) + k_S dT_c/dt + a/2 |w| + k_g . f              (forward, true rate w)
//
// Terms: bias polynomial in coil temperature T_c; scale factor as a bicubic surface on a (T, w) grid or as
// polynomials in T and w; optional Shupe k_S, scale-factor asymmetry a, g-sensitivity k_g (needs
// accel_{x,y,z}_mps2), and a thermal lag: T_c is the probe temperature through a first-order lag with time
// constant tau. Compensation inverts the forward model exactly (GyroErrorModel::inverse). The fit is in
// greybox_fit.h, the model file's JSON in greybox_json.cpp, the C export in greybox_c_export.cpp.
#pragma once

#include <string_view>

#include "model/calibration_model.h"
#include "sensor/gyro_error_model.h"

namespace gyrosid {

class GreyboxModel : public CalibrationModel {
 public:
  GreyboxModel(std::vector<std::string> features, GyroErrorModel errors, double lag_tau_s);

  std::string_view kind() const override { return "greybox"; }
  double predict(const double* x) const override;             // steady state: coil = probe
  Eigen::VectorXd predict(const Dataset& data) const override;
  bool pointwise() const override { return false; }  // runs the thermal lag over time
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<GreyboxModel> from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                 ModelTarget target);

  const GyroErrorModel& errors() const { return errors_; }
  double lag_tau_s() const { return lag_tau_s_; }
  GyroEnvironment environment(const double* x, double coil_temp_c, double coil_rate) const;

 private:
  GyroErrorModel errors_;
  double lag_tau_s_ = 0.0;
  int accel_index_ = -1;  // first of three accel features, or -1
  int temp_rate_index_ = -1;
};

}  // namespace gyrosid
