// The classical (industry) compensation of thesis s5.3.2:
//
//   error(w, T) = b(T) + [s_T(T) + s_w(w)] w
//   b(T)   = sum_{i=0..nb} beta_i v^i                 bias polynomial in temperature (cubic in the thesis)
//   s_T(T) = sum_{j=1..nt} tau_j v^j                  scale factor in temperature, "averaged over rate"
//   s_w(w) = sum_{k=0..nw} sigma_k u^k                scale factor in rate, "averaged over temperature"
//
// with u = w / w_s, v = (T - T_0) / T_s scaled for conditioning, w the measured rate. The thesis's averaging
// of the soak data over rate and over temperature is the least-squares fit of this additive separable model;
// it is solved by column-pivoted Householder QR (no normal equations).
//
// Optional (sf_cross_order nc > 0, default 0 = the thesis's model): the rate shape's coefficients move with
// temperature, s_wT(w, T) = sum_{i=1..nc} sum_{k=1..nw} gamma_ik v^i u^k, added to the bracket. An open-loop FOG's
// scale factor falls with rate^2 more steeply when hot (configs/sensors/open_loop_fog.yaml: -(650 + 5 dT +
// 0.04 dT^2) u^2 ppm); the separable form cannot hold that, and what it leaves (7 deg/h rms at 0..100 deg/s over
// -40..80 C, noise-free) is placed differently by fits that weight rates differently.
#pragma once

#include "core/solve_summary.h"
#include "model/calibration_model.h"

namespace gyrosid {

struct ClassicalOptions {
  int bias_order = 3;           // thesis fig 3.7
  int sf_temperature_order = 2; // thesis fig 3.3
  int sf_rate_order = 6;        // thesis fig 3.4
  int sf_cross_order = 0;       // temperature order of the rate shape's coefficients (0: separable, the thesis)
  std::string validate() const;
};

class ClassicalModel : public CalibrationModel {
 public:
  ClassicalModel(std::vector<std::string> features, ModelTarget target);

  std::string_view kind() const override { return "classical"; }
  using CalibrationModel::predict;
  double predict(const double* x) const override;
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<ClassicalModel> from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                   ModelTarget target);

  // The coefficients from a vector in ClassicalColumns(options)' order (below); sf_temperature's v^0 is 0.
  void set_coefficients(const ClassicalOptions& options, const Eigen::VectorXd& coefficients);

  double rate_scale = 1.0;        // w_s, rad/s
  double temperature_reference = 25.0, temperature_scale = 1.0;  // T_0, T_s (deg C)
  Eigen::VectorXd bias;           // beta_0..beta_nb, rad/s
  Eigen::VectorXd sf_temperature; // tau_1..tau_nt (index 0 unused, kept 0)
  Eigen::VectorXd sf_rate;        // sigma_0..sigma_nw
  Eigen::MatrixXd sf_cross;       // gamma_ik, row i-1 (v^i), column k-1 (u^k); empty: separable
};

// Where each coefficient group sits in classical_columns' columns (and in a vector of their coefficients):
// bias v^0..v^nb | sf_temperature v^1..v^nt w | sf_rate u^0..u^nw w | sf_cross v^i u^k w (i = 1..nc outer,
// k = 1..nw inner).
struct ClassicalColumns {
  struct Group {
    Eigen::Index first = 0, count = 0;
    Eigen::Index end() const { return first + count; }
  };
  Group bias, sf_temperature, sf_rate, sf_cross;
  explicit ClassicalColumns(const ClassicalOptions& options);
  Eigen::Index size() const { return sf_cross.end(); }
};

// The model's regression columns at measured rates w and temperatures temp (N x ClassicalColumns(options).size()),
// with the model's rate and temperature scaling.
Eigen::MatrixXd classical_columns(const ClassicalModel& model, const ClassicalOptions& options, const Eigen::VectorXd& w,
                                  const Eigen::VectorXd& temp);

// Requires features (measured_rate, temperature) in that order and target error.
std::unique_ptr<ClassicalModel> fit_classical(const Dataset& data, const ClassicalOptions& options,
                                              SolveSummary* summary = nullptr);

}  // namespace gyrosid
