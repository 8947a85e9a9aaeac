#include "model/greybox_model.h"

#include "core/error.h"
#include "model/physics_terms.h"

namespace gyrosid {

GreyboxModel::GreyboxModel(std::vector<std::string> features, GyroErrorModel errors, double lag_tau_s, std::optional<GreyboxPosterior> posterior)
    : CalibrationModel(std::move(features), ModelTarget::error), errors_(std::move(errors)), lag_tau_s_(lag_tau_s), posterior_(std::move(posterior)) {
  for (std::size_t i = 0; i < features_.size(); ++i) {
    if (features_[i] == "accel_x_mps2") accel_index_ = static_cast<int>(i);
    if (features_[i] == "temperature_rate") temp_rate_index_ = static_cast<int>(i);
  }
  if (features_.size() < 2 || features_[0] != "measured_rate" || features_[1] != "temperature") {
    fail("greybox model: the first features must be measured_rate, temperature");
  }
  if (posterior_) {
    const Eigen::Index cols = total_columns(posterior_->terms);
    if (posterior_->coefficients.size() != cols || posterior_->weights.size() != cols) {
      fail("greybox model: the posterior has ", posterior_->coefficients.size(), " coefficients and ", posterior_->weights.size(),
           " weights for ", cols, " term columns");
    }
  }
}

GyroEnvironment GreyboxModel::environment(const double* x, double coil_temp_c, double coil_rate) const {
  GyroEnvironment env;
  env.temp_c = coil_temp_c;
  env.temp_rate_c_per_s = coil_rate;
  if (accel_index_ >= 0) env.f_s = Eigen::Vector3d(x[accel_index_], x[accel_index_ + 1], x[accel_index_ + 2]);
  return env;
}

double GreyboxModel::predict(const double* x) const {
  const double rate = temp_rate_index_ >= 0 ? x[temp_rate_index_] : 0.0;
  return x[0] - errors_.inverse(x[0], environment(x, x[1], rate));
}

Eigen::VectorXd GreyboxModel::predict(const Dataset& data) const {
  Signals probe;
  probe.t_s = data.t_s;
  probe.temp_c = data.x.col(1);
  probe.rate = data.x.col(0);
  const CoilTemperature coil = coil_temperature(probe, lag_tau_s_);
  Eigen::VectorXd out(data.size());
  std::vector<double> row(static_cast<std::size_t>(data.x.cols()));
  for (Eigen::Index i = 0; i < data.size(); ++i) {
    for (Eigen::Index k = 0; k < data.x.cols(); ++k) row[static_cast<std::size_t>(k)] = data.x(i, k);
    out(i) = row[0] - errors_.inverse(row[0], environment(row.data(), coil.temp_c(i), coil.rate_c_per_s(i)));
  }
  return out;
}

Eigen::MatrixXd GreyboxModel::regressors(const Eigen::MatrixXd& x) const {
  if (!posterior_) return CalibrationModel::regressors(x);
  if (x.cols() != static_cast<Eigen::Index>(features_.size())) fail("greybox model: ", x.cols(), " input columns for ", features_.size(), " features");
  // One steady-state sample per row: coil = probe, its rate the temperature_rate input (else 0), the true rate
  // by the inversion predict(x) uses - so that predict(x_i) = h(x_i)' c to round-off.
  Signals s;
  s.t_s.assign(static_cast<std::size_t>(x.rows()), 0.0);
  s.temp_c = x.col(1);
  s.rate.resize(x.rows());
  CoilTemperature coil{x.col(1), temp_rate_index_ >= 0 ? Eigen::VectorXd(x.col(temp_rate_index_)) : Eigen::VectorXd::Zero(x.rows())};
  std::vector<double> row(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (Eigen::Index k = 0; k < x.cols(); ++k) row[static_cast<std::size_t>(k)] = x(i, k);
    s.rate(i) = errors_.inverse(row[0], environment(row.data(), row[1], coil.rate_c_per_s(i)));
  }
  for (std::size_t f = 2; f < features_.size(); ++f) s.channels[features_[f]] = x.col(static_cast<Eigen::Index>(f));
  return design_matrix(posterior_->terms, s, coil, posterior_->scaling);
}

}  // namespace gyrosid
