// Leave-one-out residuals of a regularised orthogonal least-squares model, updated recursively as columns
// are added (Chen, Hong, Harris & Sharkey 2004, eqs 19-22): with the new column w orthogonalised against the
// selected ones and its own ridge lambda,
//   g = w'y / (w'w + lambda),   e <- e - g w,   eta <- eta - w.^2 / (w'w + lambda),
// and the LOO mean square error is J = mean((e ./ eta)^2). Starts from the empty model: e = y, eta = 1.
// Shared by lrols_loo (candidate scoring) and ofs_loo (tuning each node).
#pragma once

#include <Eigen/Core>

namespace gyrosid {

class RecursiveLoo {
 public:
  explicit RecursiveLoo(const Eigen::VectorXd& y) : e_(y), eta_(Eigen::VectorXd::Ones(y.size())) {}

  // J of the current model.
  double mse() const { return (e_.array() / eta_.array().max(kFloor)).square().mean(); }
  // J after adding the orthogonalised column w with ridge lambda (the model is not changed).
  double mse_after(const Eigen::Ref<const Eigen::VectorXd>& w, const Eigen::VectorXd& y, double lambda) const {
    const double a = w.squaredNorm() + lambda, g = w.dot(y) / a;
    return ((e_ - g * w).array() / (eta_ - w.cwiseAbs2() / a).array().max(kFloor)).square().mean();
  }
  // Adds w; returns its weight g.
  double add(const Eigen::Ref<const Eigen::VectorXd>& w, const Eigen::VectorXd& y, double lambda) {
    const double a = w.squaredNorm() + lambda, g = w.dot(y) / a;
    e_ -= g * w;
    eta_ -= w.cwiseAbs2() / a;
    return g;
  }
  const Eigen::VectorXd& residuals() const { return e_; }

 private:
  static constexpr double kFloor = 1e-12;  // a sample explained entirely by one column has eta -> 0
  Eigen::VectorXd e_, eta_;
};

}  // namespace gyrosid
