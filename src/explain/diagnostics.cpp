#include "explain/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.h"
#include "core/stats.h"
#include "core/units.h"

namespace gyrosid::explain {
namespace {

// P(sup |Brownian bridge| > x).
double kolmogorov_p(double x) {
  if (x < 0.2) return 1.0;
  double p = 0.0;
  for (int j = 1; j <= 100; ++j) {
    const double term = std::exp(-2.0 * j * j * x * x);
    p += (j % 2 ? 2.0 : -2.0) * term;
    if (term < 1e-16) break;
  }
  return std::clamp(p, 0.0, 1.0);
}

Eigen::VectorXd standardized(const Eigen::VectorXd& v) {
  const double mean = v.mean();
  const double sd = std::sqrt((v.array() - mean).square().mean());
  return sd > 0 ? Eigen::VectorXd((v.array() - mean) / sd) : Eigen::VectorXd::Zero(v.size());
}

// Correlation of a and b shifted by `lag` whitened rows, over pairs that are `lag` samples apart in the recording.
double lagged_correlation(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::vector<Eigen::Index>& rows, Eigen::Index lag) {
  double sum = 0.0;
  Eigen::Index count = 0;
  const auto n = static_cast<Eigen::Index>(rows.size());
  for (Eigen::Index t = std::max<Eigen::Index>(0, lag); t < n && t - lag < n; ++t) {
    if (rows[static_cast<std::size_t>(t)] - rows[static_cast<std::size_t>(t - lag)] != lag) continue;
    sum += a(t) * b(t - lag);
    ++count;
  }
  return count ? sum / static_cast<double>(n) : 0.0;
}

// The residual whitened by the noise model over the diagnosed (training) samples, and standardised.
struct Whitened {
  Whitened(const ExplainInput& in, const Eigen::VectorXd& residual, const NoiseModel& noise)
      : w(noise, diagnosed_rows(in), in.signals.t_s), e(standardized(w.apply(residual))), n(static_cast<double>(e.size())) {}
  static std::vector<Eigen::Index> diagnosed_rows(const ExplainInput& in) {
    std::vector<Eigen::Index> rows;
    for (Eigen::Index i = 0; i < in.size(); ++i) {
      if (in.diagnosed(i)) rows.push_back(i);
    }
    return rows;
  }
  Whitener w;
  Eigen::VectorXd e;
  double n;
};

void whiteness(const Whitened& x, const NoiseModel& noise, Diagnostics& d) {
  d.ljung_box_lags = 20;
  double q = 0.0;
  for (int k = 1; k <= d.ljung_box_lags; ++k) {
    const double r = lagged_correlation(x.e, x.e, x.w.rows(), k);
    q += r * r / (x.n - k);
  }
  d.ljung_box_q = x.n * (x.n + 2.0) * q;
  d.ljung_box_dof = std::max(1, d.ljung_box_lags - noise.parameters());
  d.ljung_box_p = 1.0 - stats::chi2_cdf(d.ljung_box_q, d.ljung_box_dof);
}

// The slow channels every recording has, then the recorded ones.
std::vector<std::pair<std::string, Eigen::VectorXd>> diagnostic_channels(const ExplainInput& in) {
  std::vector<std::pair<std::string, Eigen::VectorXd>> channels;
  const Signals& s = in.signals;
  const CoilTemperature probe = coil_temperature(s, 0.0);
  channels.emplace_back("temp_c", s.temp_c);
  channels.emplace_back("temperature_rate", probe.rate_c_per_s);
  channels.emplace_back("rate_dps", s.rate / units::kDegToRad);
  channels.emplace_back("abs_rate_dps", s.rate.cwiseAbs() / units::kDegToRad);
  channels.emplace_back("t_s", Eigen::Map<const Eigen::VectorXd>(s.t_s.data(), s.size()));
  for (const auto* group : {&in.accel, &in.magnetic, &in.cross_axis, &in.aux}) {
    for (const auto& name : *group) channels.emplace_back(name, s.channel(name));
  }
  return channels;
}

// Correlation with every channel through the same whitening filter, at lags up to 600 s either way.
void channel_correlations(const ExplainInput& in, const Whitened& x, double alpha, Diagnostics& d) {
  const auto channels = diagnostic_channels(in);
  const Eigen::Index max_lag = std::max<Eigen::Index>(1, std::min<Eigen::Index>(static_cast<Eigen::Index>(600.0 / in.dt_s), x.e.size() / 10));
  std::vector<Eigen::Index> lags;
  for (int k = -20; k <= 20; ++k) {
    const Eigen::Index lag = static_cast<Eigen::Index>(std::llround(static_cast<double>(max_lag) * k / 20.0));
    if (lags.empty() || lags.back() != lag) lags.push_back(lag);
  }
  const double z_channel = stats::normal_quantile(1.0 - alpha / (2.0 * static_cast<double>(lags.size() * channels.size())));
  for (const auto& [name, values] : channels) {
    ChannelCorrelation c;
    c.channel = name;
    c.threshold = z_channel / std::sqrt(x.n);
    const double span = values.maxCoeff() - values.minCoeff();
    if (!(span > 1e-9 * std::max(1.0, values.cwiseAbs().maxCoeff()))) continue;  // constant: nothing to correlate
    const Eigen::VectorXd cw = standardized(x.w.apply(values));
    for (Eigen::Index lag : lags) {
      const double r = lagged_correlation(x.e, cw, x.w.rows(), lag);
      c.lag_s.push_back(static_cast<double>(lag) * in.dt_s);
      c.r.push_back(r);
      if (std::abs(r) > std::abs(c.peak_r)) c.peak_r = r, c.peak_lag_s = static_cast<double>(lag) * in.dt_s;
    }
    c.significant = std::abs(c.peak_r) > c.threshold;
    d.channels.push_back(c);
  }
}

// Change points in time: binary segmentation by CUSUM of the whitened residual; each final segment's mean
// against the rest's, with the noise model's variance of means of that length.
void time_windows(const ExplainInput& in, const Eigen::VectorXd& residual, const Whitened& x, double alpha, Diagnostics& d) {
  const Eigen::VectorXd& e = x.e;
  const double n = x.n;
  const Signals& s = in.signals;
  const auto total = static_cast<Eigen::Index>(e.size());
  const Eigen::Index min_len = std::max<Eigen::Index>(30, total / 50);
  const int max_tests = 31;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> segments;  // whitened rows [lo, hi)
  std::function<void(Eigen::Index, Eigen::Index, int)> split = [&](Eigen::Index lo, Eigen::Index hi, int depth) {
    const Eigen::Index len = hi - lo;
    if (depth < 5 && len >= 2 * min_len) {
      const double mean = e.segment(lo, len).mean();
      double sum = 0.0, peak = 0.0;
      Eigen::Index at = -1;
      for (Eigen::Index k = lo; k < hi - 1; ++k) {
        sum += e(k) - mean;
        if (k - lo + 1 >= min_len && hi - k - 1 >= min_len && std::abs(sum) > peak) peak = std::abs(sum), at = k;
      }
      if (at >= 0 && kolmogorov_p(peak / std::sqrt(static_cast<double>(len))) < alpha / max_tests) {
        split(lo, at + 1, depth + 1);
        split(at + 1, hi, depth + 1);
        return;
      }
    }
    segments.emplace_back(lo, hi);
  };
  split(0, total, 0);
  d.window_threshold = stats::normal_quantile(1.0 - alpha / (2.0 * static_cast<double>(segments.size())));
  const auto& rows = x.w.rows();
  for (const auto& [lo, hi] : segments) {
    TimeWindow t;
    const Eigen::Index first = rows[static_cast<std::size_t>(lo)], last = rows[static_cast<std::size_t>(hi - 1)];
    t.t_start_s = s.t_s[static_cast<std::size_t>(first)];
    t.t_end_s = s.t_s[static_cast<std::size_t>(last)];
    t.mean_dph = residual.segment(first, last - first + 1).mean();
    // In the whitened residual (unit variance, white under the noise model) the segment's mean against the
    // rest's is N(0, 1/len + 1/rest).
    const double len = static_cast<double>(hi - lo), rest = n - len;
    const double mean_in = e.segment(lo, hi - lo).mean();
    const double mean_out = rest > 0 ? (e.sum() - mean_in * len) / rest : 0.0;
    t.z = rest > 0 ? (mean_in - mean_out) / std::sqrt(1.0 / len + 1.0 / rest) : 0.0;
    d.windows.push_back(t);
  }
}

// Mean residual over (T, omega), heating and cooling apart.
void grid_cells(const ExplainInput& in, const Eigen::VectorXd& residual, const Whitened& x, double alpha, Diagnostics& d) {
  const Eigen::VectorXd& e = x.e;
  const auto& rows = x.w.rows();
  const Signals& s = in.signals;
  const CoilTemperature probe = coil_temperature(s, 0.0);
  const Eigen::VectorXd branch = thermal_branch(s, probe, TermScaling{});
  const double t_lo = s.temp_c.minCoeff(), t_hi = s.temp_c.maxCoeff();
  const Eigen::VectorXd rate_dps = s.rate / units::kDegToRad;
  const double w_lo = rate_dps.minCoeff(), w_hi = rate_dps.maxCoeff();
  const int t_bins = t_hi - t_lo > 1.0 ? 6 : 1, w_bins = w_hi - w_lo > 2.0 ? 5 : 1;
  const int cells = t_bins * w_bins * 2;
  std::vector<double> sum(static_cast<std::size_t>(cells), 0.0);
  std::vector<int> count(static_cast<std::size_t>(cells), 0);
  std::vector<double> first(static_cast<std::size_t>(cells), 0.0), last(static_cast<std::size_t>(cells), 0.0);
  // Cell means of the raw residual are reported; the test uses the whitened residual, white with unit
  // variance under the noise model, so a cell spread over the record is not judged against a wander.
  std::vector<double> sum_white(static_cast<std::size_t>(cells), 0.0);
  std::vector<int> count_white(static_cast<std::size_t>(cells), 0);
  std::vector<int> cell_of(static_cast<std::size_t>(residual.size()), 0);
  for (Eigen::Index i = 0; i < residual.size(); ++i) {
    if (!in.diagnosed(i)) continue;
    const int ti = std::min(t_bins - 1, static_cast<int>(t_bins * (s.temp_c(i) - t_lo) / std::max(t_hi - t_lo, 1e-9)));
    const int wi = std::min(w_bins - 1, static_cast<int>(w_bins * (rate_dps(i) - w_lo) / std::max(w_hi - w_lo, 1e-9)));
    const int bi = branch(i) >= 0 ? 0 : 1;
    const auto c = static_cast<std::size_t>((ti * w_bins + wi) * 2 + bi);
    cell_of[static_cast<std::size_t>(i)] = static_cast<int>(c);
    if (count[c] == 0) first[c] = s.t_s[static_cast<std::size_t>(i)];
    last[c] = s.t_s[static_cast<std::size_t>(i)];
    sum[c] += residual(i);
    ++count[c];
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto c = static_cast<std::size_t>(cell_of[static_cast<std::size_t>(rows[r])]);
    sum_white[c] += e(static_cast<Eigen::Index>(r));
    ++count_white[c];
  }
  int tested = 0;
  for (int c = 0; c < cells; ++c) tested += count[static_cast<std::size_t>(c)] >= 30;
  d.cell_threshold = stats::normal_quantile(1.0 - alpha / (2.0 * std::max(1, tested)));
  for (int c = 0; c < cells; ++c) {
    const auto k = static_cast<std::size_t>(c);
    if (count[k] < 30) continue;
    GridCell g;
    const int ti = c / 2 / w_bins, wi = c / 2 % w_bins;
    g.temp_lo_c = t_lo + (t_hi - t_lo) * ti / t_bins, g.temp_hi_c = t_lo + (t_hi - t_lo) * (ti + 1) / t_bins;
    g.rate_lo_dps = w_lo + (w_hi - w_lo) * wi / w_bins, g.rate_hi_dps = w_lo + (w_hi - w_lo) * (wi + 1) / w_bins;
    g.heating = c % 2 == 0;
    g.samples = count[k];
    g.mean_dph = sum[k] / count[k];
    g.z = count_white[k] ? sum_white[k] / std::sqrt(static_cast<double>(count_white[k])) : 0.0;
    g.t_start_s = first[k], g.t_end_s = last[k];
    d.cells.push_back(g);
  }
}

// Noise terms from the Allan deviation of the longest uniformly sampled stretch.
void noise_terms(const ExplainInput& in, const Eigen::VectorXd& residual, const NoiseModel& noise, Diagnostics& d) {
  Eigen::Index best_lo = 0, best_len = 0;
  for (Eigen::Index i = 0, lo = 0; i <= residual.size(); ++i) {
    if (i == residual.size() || in.segment[static_cast<std::size_t>(i)] != in.segment[static_cast<std::size_t>(lo)]) {
      if (i - lo > best_len) best_lo = lo, best_len = i - lo;
      lo = i;
    }
  }
  if (best_len >= 1000) {
    const std::vector<double> stretch(residual.data() + best_lo, residual.data() + best_lo + best_len);
    d.allan = overlapping_allan_deviation(stretch, in.dt_s);
    d.allan_fit = identify_noise(stretch, in.dt_s);
    const CompositeNoise& f = d.allan_fit.model;
    if (f.white > 0) d.noise_terms.push_back({"white", {{"arw_deg_per_rt_h", f.white / 60.0}}});
    if (f.quantization > 0) d.noise_terms.push_back({"quantization", {{"q_arcsec", f.quantization}}});
    for (const auto& gm : f.gauss_markov) d.noise_terms.push_back({"gauss_markov", {{"sigma_dph", gm.sigma}, {"tau_s", gm.tau_s}}});
    if (f.flicker > 0) d.noise_terms.push_back({"bias_instability", {{"b_dph", f.flicker}}});
    if (f.random_walk > 0) d.noise_terms.push_back({"rate_random_walk", {{"k_dph_per_rt_h", f.random_walk * 60.0}}});
    if (f.ramp > 0) d.noise_terms.push_back({"rate_ramp", {{"r_dph_per_h", f.ramp * 3600.0}}});
  } else {
    // Too short for an Allan fit (bursts): the whitening model's own terms, in the same units.
    d.noise_terms.push_back({"white", {{"arw_deg_per_rt_h", std::sqrt(noise.white_var * noise.dt_s) / 60.0}}});
    if (noise.gm_var > 0) d.noise_terms.push_back({"gauss_markov", {{"sigma_dph", std::sqrt(noise.gm_var)}, {"tau_s", noise.gm_tau_s}}});
    if (noise.rw_q > 0) d.noise_terms.push_back({"rate_random_walk", {{"k_dph_per_rt_h", std::sqrt(noise.rw_q / noise.dt_s) * 60.0}}});
  }
}

}  // namespace

Diagnostics diagnose(const ExplainInput& in, const Eigen::VectorXd& residual, const NoiseModel& noise, double alpha) {
  Diagnostics d;
  d.noise = noise;
  const Whitened x(in, residual, noise);
  whiteness(x, noise, d);
  // Any of the three families (channels, time windows, cells) reports unexplained structure, so each gets a
  // third of alpha (Bonferroni across the families): the recording's false alarm stays at most alpha.
  const double family_alpha = alpha / 3.0;
  channel_correlations(in, x, family_alpha, d);
  time_windows(in, residual, x, family_alpha, d);
  grid_cells(in, residual, x, family_alpha, d);
  noise_terms(in, residual, noise, d);
  return d;
}

std::string_view describe_noise(std::string_view id) {
  if (id == "white") return "angle random walk: white rate noise (photon shot noise, detector electronics); Allan slope -1/2";
  if (id == "quantization") return "quantization of the output; Allan slope -1";
  if (id == "bias_instability") return "flicker noise of the bias; the flat floor of the Allan curve";
  if (id == "gauss_markov") return "exponentially correlated bias noise; a bump in the Allan curve";
  if (id == "rate_random_walk") return "random walk of the bias; Allan slope +1/2";
  if (id == "rate_ramp") return "a steady bias ramp over the record; Allan slope +1";
  return "";
}

}  // namespace gyrosid::explain
