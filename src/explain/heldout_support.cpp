#include "explain/heldout_support.h"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>

namespace gyrosid::explain {

std::vector<char> outside_training_support(const Eigen::MatrixXd& x, const std::vector<char>& heldout, double ratio) {
  const Eigen::Index n = x.rows(), p = x.cols();
  std::vector<char> out(static_cast<std::size_t>(n), 0);
  std::vector<Eigen::Index> train, held;
  for (Eigen::Index i = 0; i < n; ++i) (heldout[static_cast<std::size_t>(i)] ? held : train).push_back(i);
  if (p == 0 || held.empty() || static_cast<Eigen::Index>(train.size()) <= p) return out;
  Eigen::MatrixXd xt(static_cast<Eigen::Index>(train.size()), p);
  for (std::size_t r = 0; r < train.size(); ++r) xt.row(static_cast<Eigen::Index>(r)) = x.row(train[r]);
  // Unit-norm training columns; a column that is zero on the training rows keeps its full norm, so a
  // held-out sample where it is not zero lies along an undetermined direction.
  Eigen::VectorXd scale(p);
  for (Eigen::Index c = 0; c < p; ++c) {
    const double s = xt.col(c).norm(), all = x.col(c).norm();
    scale(c) = s > 0 ? s : (all > 0 ? all : 1.0);
  }
  xt = xt * scale.cwiseInverse().asDiagonal();
  // X = Q R, so X'X = R'R and h = |S^-1 V' x|^2 with R = U S V'.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(xt);
  const Eigen::MatrixXd r = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r, Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  if (!(s(0) > 0)) return out;
  const double floor = 1e-6 * s(0);
  const auto rank = static_cast<double>((s.array() > floor).count());
  const Eigen::VectorXd inv = s.cwiseMax(floor).cwiseInverse();
  const double threshold = ratio * rank / static_cast<double>(train.size());
  for (Eigen::Index i : held) {
    const Eigen::VectorXd z = inv.asDiagonal() * (svd.matrixV().transpose() * x.row(i).transpose().cwiseQuotient(scale));
    out[static_cast<std::size_t>(i)] = z.squaredNorm() > threshold;
  }
  return out;
}

namespace {

// What identifies a model's columns on a recording: its terms (kinds, orders, grids, parameters) and lag.
nlohmann::json model_key(const ModelSpec& m) {
  nlohmann::json terms = nlohmann::json::array();
  for (const Term& t : m.terms) terms.push_back(t.to_json());
  return {{"terms", terms}, {"lag_tau_s", m.lag_tau_s}};
}

}  // namespace

HeldoutSupport::HeldoutSupport(const ExplainInput& in, const ModelSpec& base, const TermScaling& scaling, double ratio)
    : in_(in), scaling_(scaling), ratio_(ratio), base_(outside_training_support(model_columns(base, in.signals, scaling), in.heldout, ratio)) {}

const std::vector<char>& HeldoutSupport::of(const ModelSpec& model) {
  nlohmann::json key = model_key(model);
  for (const auto& [k, mask] : cache_) {
    if (k == key) return mask;
  }
  std::vector<char> mask = outside_training_support(model_columns(model, in_.signals, scaling_), in_.heldout, ratio_);
  for (const Term& t : model.terms) {
    const auto p = t.parameter();
    if (!p || p->scale) continue;
    if (const auto run = in_.heldout_run_at(p->value)) {
      for (Eigen::Index i = run->first; i <= run->second; ++i) mask[static_cast<std::size_t>(i)] = 1;
    }
  }
  cache_.emplace_back(std::move(key), std::move(mask));
  return cache_.back().second;
}

std::vector<char> HeldoutSupport::outside(const std::vector<const ModelSpec*>& models) {
  std::vector<char> out = base_;
  for (const ModelSpec* m : models) {
    const std::vector<char>& mask = of(*m);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = out[i] || mask[i];
  }
  return out;
}

}  // namespace gyrosid::explain
