// Grey-box calibration model: the unified sensor model of src/sensor (thesis eq 3.48) with its coefficients
// estimated from a recording - the "simulation" the missing-physics finder compares recordings against.
//
//   w_meas = w + dSF(T_c, w) w + b(T_c) + k_S dT_c/dt + a/2 |w| + k_g . f              (forward, true rate w)
//
// Terms: bias polynomial in coil temperature T_c; scale factor as a bicubic surface on a (T, w) grid (its
// values enter linearly) or as polynomials in T and w; optional Shupe k_S, scale-factor asymmetry a,
// g-sensitivity k_g (needs accel_{x,y,z}_mps2), and a thermal lag: T_c is the probe temperature through a
// first-order lag with time constant tau (nonlinear, estimated by NLopt's BOBYQA around an inner linear
// least-squares solve). Given tau every coefficient is linear: they are fitted in the forward direction
// (the physics is defined on the true rate) by column-pivoted QR with a small ridge.
// Compensation inverts the forward model exactly (GyroErrorModel::inverse).
#pragma once

#include <array>
#include <string_view>
#include <utility>

#include "core/enum_names.h"
#include "model/calibration_model.h"
#include "sensor/gyro_error_model.h"

namespace gyrosid {

enum class ScaleFactorForm { surface, polynomial };

template <>
struct EnumNames<ScaleFactorForm> {
  static constexpr std::string_view kNoun = "scale-factor form";
  static constexpr std::array<std::pair<ScaleFactorForm, std::string_view>, 2> kTable{
      {{ScaleFactorForm::surface, "surface"}, {ScaleFactorForm::polynomial, "polynomial"}}};
};

struct GreyboxOptions {
  int bias_order = 3;
  ScaleFactorForm scale_factor = ScaleFactorForm::surface;
  std::vector<double> surface_temperatures_c{-20, 0, 20, 25, 40, 60};  // the thesis grid
  std::vector<double> surface_rates_dps{-100, -80, -60, -40, -20, -10, 10, 20, 40, 60, 80, 100};
  int sf_temperature_order = 2;
  int sf_rate_order = 6;
  bool shupe = false;
  bool asymmetry = false;
  bool g_sensitivity = false;
  bool thermal_lag = false;
  double lag_max_s = 3600.0;
  double ridge = 1e-9;  // relative to the scaled normal-matrix norm, for grid cells the data never visits
  std::string validate() const;
};

class GreyboxModel : public CalibrationModel {
 public:
  GreyboxModel(std::vector<std::string> features, GyroErrorModel errors, double lag_tau_s);

  std::string_view kind() const override { return "greybox"; }
  double predict(const double* x) const override;             // steady state: coil = probe
  Eigen::VectorXd predict(const Dataset& data) const override;  // runs the thermal lag over time
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

struct GreyboxFitSummary {
  std::size_t samples = 0;
  std::size_t parameters = 0;
  double rms_residual_dph = 0.0;
  double lag_tau_s = 0.0;
  int lag_evaluations = 0;
  double time_s = 0.0;
  nlohmann::json to_json() const;
};

// Features: measured_rate, temperature (+ accel_x_mps2, accel_y_mps2, accel_z_mps2 for g-sensitivity).
std::unique_ptr<GreyboxModel> fit_greybox(const Dataset& data, const GreyboxOptions& options,
                                          GreyboxFitSummary* summary = nullptr);
std::vector<std::string> greybox_features(const GreyboxOptions& options);

}  // namespace gyrosid
