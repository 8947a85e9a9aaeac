// Residual diagnostics (Ljung's system identification, ch. 16): whiteness, correlation with every recorded
// channel, structure in time and over (T, omega), and the residual's noise terms.
//
//   Ljung-Box   Q = n (n + 2) sum_{k<=h} r_k^2 / (n - k) on the whitened residual, chi-square with h - p dof
//               (p the noise model's parameters: the fitted noise is accounted for);
//   channels    correlation of the whitened residual with each channel through the same filter, at lags; with a
//               white residual its standard error is 1/sqrt(n) whatever the channel's own correlation;
//   time        binary segmentation by CUSUM of the whitened residual (Kolmogorov p-values); each segment's mean
//               against the noise model's Allan variance at its length;
//   (T, omega)  mean residual per cell, heating and cooling apart, against the noise model's Allan variance at
//               the cell's length (conservative for cells spread over the record);
//   noise       overlapping Allan deviation of the residual and its IEEE Std 952 terms.
// Thresholds are Bonferroni-corrected over the lags, channels, segments or cells tested, and across the three
// families that report unexplained structure (channels, time, cells: alpha / 3 each). Only training
// samples are diagnosed (ExplainInput::diagnosed): held out, the residual carries the simulation's
// prediction error, which a cell or window test would read as structure.
#pragma once

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "explain/explain_input.h"
#include "noise/state_space.h"
#include "noise/allan.h"
#include "noise/identify.h"

namespace gyrosid::explain {

struct ChannelCorrelation {
  std::string channel;
  std::vector<double> lag_s, r;
  double peak_r = 0.0, peak_lag_s = 0.0, threshold = 0.0;
  bool significant = false;
};

struct TimeWindow {
  double t_start_s = 0.0, t_end_s = 0.0;
  double mean_dph = 0.0, z = 0.0;
};

struct GridCell {
  double temp_lo_c = 0.0, temp_hi_c = 0.0, rate_lo_dps = 0.0, rate_hi_dps = 0.0;
  bool heating = true;
  int samples = 0;
  double mean_dph = 0.0, z = 0.0;
  double t_start_s = 0.0, t_end_s = 0.0;
};

// An IEEE Std 952 noise term of the residual: its id (white, quantization, bias_instability, gauss_markov,
// rate_random_walk, rate_ramp) and its coefficients by name, with units in the names.
struct NoiseTerm {
  std::string id;
  std::vector<std::pair<std::string, double>> coefficients;
};
// What a noise term is, in a sentence.
std::string_view describe_noise(std::string_view noise_id);

struct Diagnostics {
  double ljung_box_q = 0.0, ljung_box_p = 1.0;
  int ljung_box_lags = 0, ljung_box_dof = 0;
  std::vector<ChannelCorrelation> channels;
  std::vector<TimeWindow> windows;          // segments of the change-point search; significant ones flagged by z
  double window_threshold = 0.0;
  std::vector<GridCell> cells;
  double cell_threshold = 0.0;
  std::vector<AllanPoint> allan;            // deg/h; empty if no uniformly sampled stretch is long enough
  NoiseIdentification allan_fit;           // the noise identification of that stretch (noise/identify.h)
  std::vector<NoiseTerm> noise_terms;
  NoiseModel noise;                         // the whitening model the tests assume
};

// `residual_dph` on every sample; `noise` the whitening model.
Diagnostics diagnose(const ExplainInput& in, const Eigen::VectorXd& residual_dph, const NoiseModel& noise, double alpha);

}  // namespace gyrosid::explain
