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
//
// A model fitted under a lot's prior (estimate_greybox) also carries the Gaussian posterior of its linear
// coefficients at the found lag (issue 33): the error in steady state is linear in them,
//   e(w, T, f) = x(w, T, f)' c,   c ~ N(c_MAP, P)        x the physics terms' columns (physics_terms.h)
// so regressors(x) = x(w~, T, f) at the true rate w~ = inverse(m) of the measured m (as predict(x) inverts),
// and the predictive sigma is sqrt(x' P x) (weight_posterior.h; Bishop, PRML eq 3.59 without the noise term: the
// sd of the estimated error, not of a new measurement).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "model/calibration_model.h"
#include "model/physics_terms.h"
#include "sensor/gyro_error_model.h"

namespace gyrosid {

// The coefficients a greybox fit solved for, with their posterior: the terms' columns under `scaling`, in
// the fit's coefficient order (greybox_terms), their values (the posterior mean, which the error model's
// parameters hold too) and the Gaussian over them.
struct GreyboxPosterior {
  TermScaling scaling;
  std::vector<Term> terms;
  Eigen::VectorXd coefficients;
  WeightPosterior weights;
};

class GreyboxModel : public CalibrationModel {
 public:
  GreyboxModel(std::vector<std::string> features, GyroErrorModel errors, double lag_tau_s,
               std::optional<GreyboxPosterior> posterior = std::nullopt);

  std::string_view kind() const override { return "greybox"; }
  double predict(const double* x) const override;             // steady state: coil = probe
  Eigen::VectorXd predict(const Dataset& data) const override;
  bool pointwise() const override { return false; }  // runs the thermal lag over time
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<GreyboxModel> from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                 ModelTarget target);
  // Null for a fit without a prior (its ridge leaves the variance of unvisited grid cells meaningless).
  const WeightPosterior* posterior() const override { return posterior_ ? &posterior_->weights : nullptr; }
  Eigen::MatrixXd regressors(const Eigen::MatrixXd& x) const override;
  const GreyboxPosterior* coefficient_posterior() const { return posterior_ ? &*posterior_ : nullptr; }

  const GyroErrorModel& errors() const { return errors_; }
  double lag_tau_s() const { return lag_tau_s_; }
  GyroEnvironment environment(const double* x, double coil_temp_c, double coil_rate) const;

 private:
  GyroErrorModel errors_;
  double lag_tau_s_ = 0.0;
  int accel_index_ = -1;  // first of three accel features, or -1
  int temp_rate_index_ = -1;
  std::optional<GreyboxPosterior> posterior_;
};

}  // namespace gyrosid
