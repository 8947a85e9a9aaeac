// Random drift D_R of one gyro axis (thesis eq 3.5, IEEE Std 952 Annex C): angle random walk N, bias
// instability B, rate random walk K, first-order Gauss-Markov processes (thesis eqs 3.52-3.55) and rate
// ramp R. Quantization Q is an output effect and lives in gyro_sensor.h.
//
// A gyro sample is the mean rate over its sample interval (angle increment / dt), so every process is
// generated as its exact interval average - jointly with its end state, from their Gaussian joint law -
// rather than as a point sample, and the discretisation is exact, not Euler (thesis eq 3.55 uses Euler,
// which misstates the variance when dt is not much smaller than tau). With h = dt, phi = e^{-h/tau}:
//   white rate noise:  mean ~ N(0, N^2 / h)
//   Gauss-Markov dx = -x/tau dt + q dW, q^2 = 2 sigma^2 / tau, started stationary N(0, sigma^2):
//     x_k = phi x_{k-1} + w1,  integral = tau (1 - phi) x_{k-1} + w2,
//     var w1 = q^2 tau (1 - phi^2)/2,  var w2 = q^2 tau^2 (h - 2 tau (1 - phi) + tau (1 - phi^2)/2),
//     cov = q^2 tau^2 ((1 - phi) - (1 - phi^2)/2)
//   rate random walk (intensity K), b_0 = 0:
//     b_k = b_{k-1} + w1,  integral = h b_{k-1} + w2,  var w1 = K^2 h, var w2 = K^2 h^3/3, cov = K^2 h^2/2
//   rate ramp:  R t
// so the Allan variance of the output equals the continuous-time formulas at every tau >= dt.
// Bias instability (a 1/f process, which has no finite-state realisation) is realised as a sum of
// Gauss-Markov processes with correlation times log-uniform over a band and equal variances - a sum of
// Lorentzians whose spectrum is 1/f inside the band - scaled so that its Allan deviation in the band equals
// the flicker floor sqrt(2 ln 2 / pi) B = 0.664 B.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/random.h"

namespace gyrosid {

struct GaussMarkov {
  double sigma_radps = 0.0;  // stationary standard deviation
  double tau_s = 0.0;        // correlation time
};

struct NoiseOptions {
  double arw_rad_rt_s = 0.0;            // N
  double bias_instability_radps = 0.0;  // B
  double bias_instability_tau_min_s = 0.1;  // band of the 1/f realisation: cover the averaging times of interest
  double bias_instability_tau_max_s = 1e5;
  int bias_instability_per_decade = 3;  // Gauss-Markov components per decade of the band
  double rrw_rad_s_rt_s = 0.0;          // K
  std::vector<GaussMarkov> gauss_markov;
  double rate_ramp_radps2 = 0.0;        // R

  std::string validate() const;  // empty when valid, else names the offending option and its range
  bool any() const;
};

// Allan variance of a continuous first-order Gauss-Markov process at averaging time T:
//   sigma_A^2(T) = (2 sigma^2 tau / T) [1 - (tau / 2T)(3 - 4 e^{-T/tau} + e^{-2T/tau})]
// (-> white noise 2 sigma^2 tau / T for T >> tau, rate random walk (2 sigma^2/tau) T/3 for T << tau).
double gauss_markov_allan_variance(double sigma, double tau_c, double averaging_time);

// The Gauss-Markov components that realise bias instability B over [tau_min, tau_max].
std::vector<GaussMarkov> bias_instability_components(double b_radps, double tau_min_s, double tau_max_s,
                                                     int per_decade);

class NoiseGenerator {
 public:
  NoiseGenerator(const NoiseOptions& options, std::uint64_t seed, std::string_view stream);
  // Noise (rad/s) of the sample at time t_s; dt_s is its interval to the previous sample (> 0).
  double next(double t_s, double dt_s);

 private:
  struct Markov {
    GaussMarkov process;
    double state;
    RandomStream random;
    // Step coefficients for the last step length h (recomputed only when h changes).
    double h = -1.0, phi = 0.0, carry = 0.0, v11 = 0.0, v12 = 0.0, v22 = 0.0;
  };
  // Draws (end-state increment w1, integral increment w2) with covariance [[v11, v12], [v12, v22]].
  static std::pair<double, double> correlated_pair(RandomStream& random, double v11, double v12, double v22);
  NoiseOptions options_;
  RandomStream white_, rrw_;
  std::vector<Markov> markov_;
  double rrw_state_ = 0.0;
};

}  // namespace gyrosid
