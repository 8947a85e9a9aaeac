// The Gaussian log-likelihood of a regression under the coloured-noise model (noise/state_space.h),
// maximised over the noise: the random-walk and Gauss-Markov variances relative to the white one and the
// Gauss-Markov time constant (BOBYQA over their logarithms, from the Allan fit's; the Allan fit places a
// weak slow wander poorly under strong white noise, and a wander with the wrong time constant is what a
// slow deterministic term then absorbs), the linear coefficients
// and the white variance concentrated out (Kalman-whitened least squares; the whitener's log-determinant
// is the determinant term). Comparing it with and without a deterministic term tells an effect from
// coloured noise that mimics it: a true trend or step takes the random walk's place, a wander is not
// bettered by one.
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

#include "noise/state_space.h"

namespace gyrosid::explain {

// w.apply(x), the columns whitened in (up to) two groups at once: each column's filter is its own recursion,
// so the result is the same whatever the thread count.
Eigen::MatrixXd whiten_columns(const Whitener& w, const Eigen::MatrixXd& x);

class NoiseLikelihood {
 public:
  // rows: the samples (ascending); t_s: every sample's time; start: the Allan fit's model; xtol: the
  // search's tolerance in the log ratios (1e-2 moves log L by about 0.01 against 1e-3 on the concealed-effects
  // recordings, with a fifth fewer evaluations).
  NoiseLikelihood(std::vector<Eigen::Index> rows, const std::vector<double>& t_s, const NoiseModel& start, double xtol = 1e-3);

  struct Optimum {
    double log_likelihood = 0.0;
    // log(random-walk q / white), log(Gauss-Markov variance / white), log(Gauss-Markov tau / s)
    std::array<double, 3> log_ratios{};
  };
  // Maximised from the start model's ratios, or from `from` (a nested model's optimum: the larger model's
  // maximum is then never below the smaller's).
  Optimum maximise(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) const;
  Optimum maximise(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Optimum& from) const;
  // The start model's ratios (log likelihood not evaluated).
  Optimum start() const;
  std::size_t samples() const { return rows_.size(); }
  // The noise model at an optimum's ratios, the white variance 1 (a whitener's residual is then in units of it).
  NoiseModel model(const Optimum& at) const;

 private:
  double negative(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const std::array<double, 3>& v) const;

  std::vector<Eigen::Index> rows_;
  const std::vector<double>& t_s_;
  NoiseModel start_;
  double gm_tau_s_;
  double max_log_tau_;  // the Gauss-Markov time constant at most a third of the span
  double xtol_;
};

// The noise model of a residual (on `rows`, ascending) by maximum likelihood about a constant, started
// from `start` (its Allan fit, which under strong white noise misplaces a weak slow wander - the residual
// diagnostics would then read the wander as structure): the white variance concentrated out; slow parts
// below 1e-6 of the white variance (Gauss-Markov) or 1e-10 of it per sample (random walk) dropped.
NoiseModel likelihood_noise_model(const Eigen::VectorXd& residual, const std::vector<Eigen::Index>& rows, const std::vector<double>& t_s,
                                  const NoiseModel& start);

}  // namespace gyrosid::explain
