// The model `gyrosid explain` writes: an optional prior model (the simulation the recording was compared
// with) plus the physics terms that were re-estimated or found missing (physics_terms.h):
//
//   e = g * prior(x) + sum_c beta_c x_c(t),      coil temperature through a first-order lag tau if modelled
//
// The terms are physics on the true rate; the model's input is the measured rate, so predictions invert
// w = m - e(w) by fixed-point iteration. Along a recording (predict(Dataset)) every term is evaluated, including those with memory (thermal lag,
// hysteresis branch) or time (warm-up from the first sample, ageing). A single sample (predict(x)) is the
// steady state: coil = probe, no temperature rate, no warm-up left, ageing and hysteresis at their
// reference (zero). The C export covers models without prior and without terms that need a history.
#pragma once

#include <memory>

#include "model/calibration_model.h"
#include "model/physics_terms.h"

namespace gyrosid {

class ExplainedModel : public CalibrationModel {
 public:
  static constexpr int kInversionSteps = 4;

  ExplainedModel(TermScaling scaling, double lag_tau_s, std::vector<Term> terms, Eigen::VectorXd coefficients,
                 std::unique_ptr<CalibrationModel> prior = nullptr, double prior_gain = 1.0);

  std::string_view kind() const override { return "explained"; }
  double predict(const double* x) const override;
  Eigen::VectorXd predict(const Dataset& data) const override;
  bool pointwise() const override { return false; }
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<ExplainedModel> from_json(const nlohmann::json& j, const std::string& source);

  const std::vector<Term>& terms() const { return terms_; }
  const Eigen::VectorXd& coefficients() const { return coefficients_; }
  double lag_tau_s() const { return lag_tau_s_; }

 private:
  Signals signals_of(const Dataset& data) const;
  Dataset prior_dataset(const Dataset& data) const;

  TermScaling scaling_;
  double lag_tau_s_;
  std::vector<Term> terms_;
  Eigen::VectorXd coefficients_;
  std::unique_ptr<CalibrationModel> prior_;
  double prior_gain_;
};

// The features a set of terms (and a prior) read: measured_rate, temperature, then every named channel.
std::vector<std::string> explained_features(const std::vector<Term>& terms, const CalibrationModel* prior);

}  // namespace gyrosid
