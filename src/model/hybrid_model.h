// The hybrid model (issue 11): grey-box physics where the physics is known, plus a Gaussian RBF network on
// what the physics leaves, both functions of the true rate w and the temperature T:
//
//   e(w, T) = sum_c beta_c x_c(w, T) + b(w, T),   x_c the physics terms' columns (model/physics_terms.h:
//             bias, bias in temperature, scale-factor polynomial or surface, asymmetry; steady state),
//             b an RbfNetwork evaluated at (w, T) (its own normalisation, no constant of its own)
//
// fitted jointly as one Bayesian linear model (solvers/bayes): flat prior on the physics coefficients, a
// Gaussian prior on the RBF weights whose width, scale and the noise are set by the evidence. Its input is
// the measured rate m, so predictions invert w = m - e(w, T) by fixed-point iteration (as the explained
// model does). The posterior covers (RBF weights, physics coefficients) in that order; regressors(x) are
// [phi(w~, T~), x_c(w, T)] at the inverted w.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "model/calibration_model.h"
#include "model/physics_terms.h"
#include "model/rbf_network.h"
#include "sensor/spline_surface.h"

namespace gyrosid {

class HybridModel : public CalibrationModel {
 public:
  HybridModel(TermScaling scaling, std::vector<Term> terms, Eigen::VectorXd coefficients, RbfNetwork rbf,
              std::optional<WeightPosterior> posterior);

  std::string_view kind() const override { return "hybrid"; }
  using CalibrationModel::predict;
  double predict(const double* x) const override;
  nlohmann::json parameters_json() const override;
  void export_c_body(CExport& out) const override;
  static std::unique_ptr<HybridModel> from_json(const nlohmann::json& j, std::vector<std::string> features, ModelTarget target,
                                                const std::string& source);
  const WeightPosterior* posterior() const override { return posterior_ ? &*posterior_ : nullptr; }
  Eigen::MatrixXd regressors(const Eigen::MatrixXd& x) const override;

  // The error at true rate w (rad/s) and temperature T, and the physics part alone.
  double error_at(double w, double temp_c) const;
  double physics_at(double w, double temp_c) const;
  // Physics columns x_c(w, T) for rates w and temperatures T (N x coefficients()).
  Eigen::MatrixXd physics_columns(const Eigen::VectorXd& w, const Eigen::VectorXd& temp_c) const;

  const std::vector<Term>& terms() const { return terms_; }
  const Eigen::VectorXd& coefficients() const { return coefficients_; }
  const TermScaling& scaling() const { return scaling_; }
  const RbfNetwork& rbf() const { return rbf_; }

 private:
  double true_rate(const double* x) const;  // w solving w = m - e(w, T)

  TermScaling scaling_;
  std::vector<Term> terms_;
  Eigen::VectorXd coefficients_;
  RbfNetwork rbf_;
  std::optional<WeightPosterior> posterior_;
  // Per term: the surface through the fitted coefficients (surface terms; the term is linear in its grid
  // values, so its contribution is omega times this one surface), else empty.
  std::vector<std::optional<SplineSurface>> surfaces_;
};

// The static terms a hybrid supports (no time, history or channels).
bool hybrid_supports(const Term& term);

}  // namespace gyrosid
