#include "model/normalizer.h"

#include "core/error.h"
#include "core/units.h"

namespace gyrosid {

Normalizer Normalizer::make(NormalizationKind kind, const std::vector<std::string>& features, const Eigen::MatrixXd& x) {
  const Eigen::Index d = static_cast<Eigen::Index>(features.size());
  Normalizer n{Eigen::VectorXd::Zero(d), Eigen::VectorXd::Ones(d)};
  for (Eigen::Index k = 0; k < d; ++k) {
    if (kind == NormalizationKind::units) {
      if (features[k] == "measured_rate") n.scale(k) = units::kDegToRad;  // x~ in deg/s
      continue;
    }
    const double lo = x.col(k).minCoeff(), hi = x.col(k).maxCoeff();
    n.offset(k) = 0.5 * (lo + hi);
    n.scale(k) = hi > lo ? 0.5 * (hi - lo) : 1.0;  // a constant input stays at 0
  }
  return n;
}

Eigen::MatrixXd Normalizer::apply(const Eigen::MatrixXd& x) const {
  return (x.rowwise() - offset.transpose()).array().rowwise() / scale.transpose().array();
}

void Normalizer::apply(const double* x, double* out) const {
  for (Eigen::Index k = 0; k < offset.size(); ++k) out[k] = (x[k] - offset(k)) / scale(k);
}

nlohmann::json Normalizer::to_json() const {
  return {{"offset", std::vector<double>(offset.data(), offset.data() + offset.size())},
          {"scale", std::vector<double>(scale.data(), scale.data() + scale.size())}};
}

Normalizer Normalizer::from_json(const nlohmann::json& j) {
  const auto o = j.at("offset").get<std::vector<double>>(), s = j.at("scale").get<std::vector<double>>();
  if (o.size() != s.size()) fail("normalizer: offset and scale differ in length");
  Normalizer n{Eigen::Map<const Eigen::VectorXd>(o.data(), static_cast<Eigen::Index>(o.size())),
               Eigen::Map<const Eigen::VectorXd>(s.data(), static_cast<Eigen::Index>(s.size()))};
  for (double v : s)
    if (!(v > 0)) fail("normalizer: scale must be positive");
  return n;
}

}  // namespace gyrosid
