#include "noise/processes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace gyrosid {

std::string NoiseOptions::validate() const {
  if (!(arw_rad_rt_s >= 0)) return "noise.arw must be >= 0";
  if (!(bias_instability_radps >= 0)) return "noise.bias_instability must be >= 0";
  if (!(rrw_rad_s_rt_s >= 0)) return "noise.rate_random_walk must be >= 0";
  if (!(bias_instability_tau_min_s > 0 && bias_instability_tau_max_s > bias_instability_tau_min_s)) {
    return "noise.bias_instability_band_s must be [tau_min, tau_max] with 0 < tau_min < tau_max";
  }
  if (bias_instability_per_decade < 1 || bias_instability_per_decade > 20) {
    return "noise.bias_instability_per_decade must be in [1, 20]";
  }
  for (const auto& gm : gauss_markov) {
    if (!(gm.sigma_radps >= 0)) return "noise.gauss_markov.sigma must be >= 0";
    if (!(gm.tau_s > 0)) return "noise.gauss_markov.tau_s must be > 0";
  }
  if (!std::isfinite(rate_ramp_radps2)) return "noise.rate_ramp must be finite";
  return "";
}

bool NoiseOptions::any() const {
  return arw_rad_rt_s > 0 || bias_instability_radps > 0 || rrw_rad_s_rt_s > 0 || !gauss_markov.empty() ||
         rate_ramp_radps2 != 0;
}

double gauss_markov_allan_variance(double sigma, double tau_c, double averaging_time) {
  const double r = averaging_time / tau_c;
  if (r < 1e-4) {
    // Series of the bracket, 1 - (3 - 4e^-r + e^-2r)/(2r) = r^2/3 - r^3/4 + ..., avoids cancellation.
    return (2.0 * sigma * sigma / r) * (r * r / 3.0 - r * r * r / 4.0);
  }
  const double bracket = 1.0 - (3.0 - 4.0 * std::exp(-r) + std::exp(-2.0 * r)) / (2.0 * r);
  return 2.0 * sigma * sigma * bracket / r;
}

std::vector<GaussMarkov> bias_instability_components(double b_radps, double tau_min_s, double tau_max_s,
                                                     int per_decade) {
  std::vector<GaussMarkov> out;
  if (b_radps <= 0) return out;
  const double decades = std::log10(tau_max_s / tau_min_s);
  const int count = std::max(2, static_cast<int>(std::ceil(decades * per_decade)) + 1);
  for (int i = 0; i < count; ++i) {
    out.push_back({1.0, tau_min_s * std::pow(tau_max_s / tau_min_s, static_cast<double>(i) / (count - 1))});
  }
  // Mean Allan variance of the unit-variance sum over the interior of the band (log-spaced), matched to
  // the flicker floor (2 ln 2 / pi) B^2.
  double mean = 0.0;
  const int samples = 41;
  const double lo = 2.0 * tau_min_s, hi = 0.5 * tau_max_s;
  for (int s = 0; s < samples; ++s) {
    const double t = lo * std::pow(hi / lo, static_cast<double>(s) / (samples - 1));
    for (const auto& gm : out) mean += gauss_markov_allan_variance(1.0, gm.tau_s, t) / samples;
  }
  const double flicker_variance = 2.0 * std::log(2.0) / std::numbers::pi * b_radps * b_radps;
  const double scale = std::sqrt(flicker_variance / mean);
  for (auto& gm : out) gm.sigma_radps = scale;
  return out;
}

NoiseGenerator::NoiseGenerator(const NoiseOptions& options, std::uint64_t seed, std::string_view stream)
    : options_(options),
      white_(seed, std::string(stream) + "/arw"),
      rrw_(seed, std::string(stream) + "/rrw") {
  const std::string problem = options.validate();
  if (!problem.empty()) fail(problem);
  int index = 0;
  auto add = [&](const GaussMarkov& gm, const std::string& name) {
    RandomStream random(seed, std::string(stream) + name + std::to_string(index++));
    const double initial = gm.sigma_radps * random.normal();
    markov_.push_back({gm, initial, random});
  };
  for (const auto& gm : options.gauss_markov) add(gm, "/gm");
  index = 0;
  for (const auto& gm : bias_instability_components(options.bias_instability_radps, options.bias_instability_tau_min_s,
                                                    options.bias_instability_tau_max_s,
                                                    options.bias_instability_per_decade)) {
    add(gm, "/bi");
  }
}

std::pair<double, double> NoiseGenerator::correlated_pair(RandomStream& random, double v11, double v12, double v22) {
  // Cholesky of the 2 x 2 covariance; the Schur complement is clamped at zero against rounding.
  const double l11 = std::sqrt(std::max(v11, 0.0));
  const double l21 = l11 > 0 ? v12 / l11 : 0.0;
  const double l22 = std::sqrt(std::max(v22 - l21 * l21, 0.0));
  const double z1 = random.normal(), z2 = random.normal();
  return {l11 * z1, l21 * z1 + l22 * z2};
}

double NoiseGenerator::next(double t_s, double dt_s) {
  const double h = dt_s;
  double n = 0.0;
  if (options_.arw_rad_rt_s > 0) n += options_.arw_rad_rt_s / std::sqrt(h) * white_.normal();
  for (auto& m : markov_) {
    if (m.h != h) {
      const double tau = m.process.tau_s, q2 = 2.0 * m.process.sigma_radps * m.process.sigma_radps / tau;
      const double one_minus_phi = -std::expm1(-h / tau), one_minus_phi2 = -std::expm1(-2.0 * h / tau);
      // h - 2 tau (1 - phi) + tau (1 - phi^2)/2 loses digits for h << tau; its series is tau (r^3/3 - r^4/4).
      const double r = h / tau;
      const double bracket = r < 1e-3 ? tau * (r * r * r / 3.0 - r * r * r * r / 4.0)
                                      : h - 2.0 * tau * one_minus_phi + tau * one_minus_phi2 / 2.0;
      m.h = h;
      m.phi = 1.0 - one_minus_phi;
      m.carry = tau * one_minus_phi;
      m.v11 = q2 * tau * one_minus_phi2 / 2.0;
      m.v12 = q2 * tau * tau * (one_minus_phi - one_minus_phi2 / 2.0);
      m.v22 = q2 * tau * tau * bracket;
    }
    const auto [w1, w2] = correlated_pair(m.random, m.v11, m.v12, m.v22);
    n += (m.carry * m.state + w2) / h;
    m.state = m.phi * m.state + w1;
  }
  if (options_.rrw_rad_s_rt_s > 0) {
    const double k2 = options_.rrw_rad_s_rt_s * options_.rrw_rad_s_rt_s;
    const auto [w1, w2] = correlated_pair(rrw_, k2 * h, k2 * h * h / 2.0, k2 * h * h * h / 3.0);
    n += (h * rrw_state_ + w2) / h;
    rrw_state_ += w1;
  }
  n += options_.rate_ramp_radps2 * t_s;
  return n;
}

}  // namespace gyrosid
