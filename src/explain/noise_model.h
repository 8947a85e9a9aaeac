// The residual's noise model for whitening: an autoregressive process
//
//   x_t + a_1 x_{t-1} + ... + a_p x_{t-p} = e_t,   e_t white with variance s^2,
//
// fitted by Burg's method over several runs of uniformly spaced samples at once (the forward and backward
// prediction-error energies summed over runs), the order chosen by BIC. Coloured gyro noise - bias
// instability, Gauss-Markov, rate random walk - is approximated well enough by a low order that the
// whitened residual supports least-squares statistics; white noise gives order 0.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace gyrosid::explain {

struct ArNoiseModel {
  std::vector<double> a;         // a_1..a_p
  double innovation_variance = 0.0;
  int order() const { return static_cast<int>(a.size()); }
};

// Runs: the rows (sample indices, ascending) split wherever the index jumps or the segment id changes.
std::vector<std::vector<Eigen::Index>> contiguous_runs(const std::vector<Eigen::Index>& rows, const std::vector<int>& segment);

ArNoiseModel fit_ar(const Eigen::VectorXd& x, const std::vector<std::vector<Eigen::Index>>& runs, int max_order);

// Applies the AR filter along each run; the first p samples of every run have no full history and are
// dropped. The whitened rows keep their sample indices (rows()).
class Whitener {
 public:
  Whitener(ArNoiseModel model, const std::vector<std::vector<Eigen::Index>>& runs);
  Eigen::MatrixXd apply(const Eigen::MatrixXd& x) const;  // x has one row per sample of the recording
  const std::vector<Eigen::Index>& rows() const { return rows_; }
  const ArNoiseModel& model() const { return model_; }

 private:
  ArNoiseModel model_;
  std::vector<Eigen::Index> rows_;
};

}  // namespace gyrosid::explain
