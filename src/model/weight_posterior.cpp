#include "model/weight_posterior.h"

#include <Eigen/Dense>

#include <cmath>
#include <vector>

#include "core/error.h"

namespace gyrosid {

Eigen::VectorXd WeightPosterior::sigma(const Eigen::MatrixXd& h) const {
  if (h.cols() != root.cols()) fail("posterior: ", h.cols(), " regressors for ", root.cols(), " weights");
  // |L' h_i| for every row: row i of h L.
  const Eigen::MatrixXd hl = h * root.triangularView<Eigen::Lower>();
  return (hl.rowwise().squaredNorm().array() + model_error_radps * model_error_radps).sqrt().matrix();
}

WeightPosterior WeightPosterior::of_covariance(const Eigen::MatrixXd& p, double noise_sigma) {
  WeightPosterior out;
  out.noise_sigma_radps = noise_sigma;
  const Eigen::Index m = p.rows();
  double jitter = 0.0;
  const double scale = p.diagonal().cwiseAbs().maxCoeff();
  for (int attempt = 0; attempt < 8; ++attempt) {
    Eigen::LLT<Eigen::MatrixXd> llt(p + jitter * Eigen::MatrixXd::Identity(m, m));
    if (llt.info() == Eigen::Success) {
      out.root = llt.matrixL();
      return out;
    }
    jitter = jitter == 0.0 ? 1e-15 * scale : 10.0 * jitter;
  }
  fail("posterior: the covariance is not positive semi-definite");
}

void WeightPosterior::scale(double factor) {
  root *= factor;
  noise_sigma_radps *= factor;
  model_error_radps *= factor;
}

nlohmann::json WeightPosterior::to_json() const {
  // The lower triangle row by row: row i holds L(i, 0..i).
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < root.rows(); ++i) {
    std::vector<double> row(static_cast<std::size_t>(i + 1));
    for (Eigen::Index k = 0; k <= i; ++k) row[static_cast<std::size_t>(k)] = root(i, k);
    rows.push_back(row);
  }
  nlohmann::json j = {{"root_lower", rows}, {"noise_sigma_radps", noise_sigma_radps}};
  if (!noise_model.is_null()) j["noise_model"] = noise_model;
  if (model_error_radps > 0) j["model_error_radps"] = model_error_radps;
  return j;
}

WeightPosterior WeightPosterior::from_json(const nlohmann::json& j, Eigen::Index weights, const std::string& source) {
  WeightPosterior p;
  const auto& rows = j.at("root_lower");
  if (static_cast<Eigen::Index>(rows.size()) != weights) {
    fail(source, ": posterior has ", rows.size(), " rows for ", weights, " weights");
  }
  p.root = Eigen::MatrixXd::Zero(weights, weights);
  for (Eigen::Index i = 0; i < weights; ++i) {
    const auto row = rows[static_cast<std::size_t>(i)].get<std::vector<double>>();
    if (static_cast<Eigen::Index>(row.size()) != i + 1) fail(source, ": posterior row ", i, " has ", row.size(), " values, expected ", i + 1);
    for (Eigen::Index k = 0; k <= i; ++k) p.root(i, k) = row[static_cast<std::size_t>(k)];
  }
  if (!p.root.allFinite()) fail(source, ": posterior has non-finite values");
  p.noise_sigma_radps = j.value("noise_sigma_radps", 0.0);
  p.model_error_radps = j.value("model_error_radps", 0.0);
  if (!(p.model_error_radps >= 0) || !std::isfinite(p.model_error_radps)) fail(source, ": posterior model_error_radps must be finite and >= 0");
  if (j.contains("noise_model")) p.noise_model = j["noise_model"];
  return p;
}

}  // namespace gyrosid
