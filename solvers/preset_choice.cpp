#include "solvers/preset_choice.h"

#include <algorithm>
#include <cmath>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/dataset.h"

namespace gyrosid {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// 1.4826 MAD / sqrt(C(2k, k)) of the k-th differences: the white-noise sigma per sample, robust to the few
// large differences where the rate programme turns.
double difference_sigma(Eigen::VectorXd e, int k) {
  double binomial = 1.0;
  for (int i = 0; i < k; ++i) {
    e = (e.tail(e.size() - 1) - e.head(e.size() - 1)).eval();
    binomial = binomial * (2 * k - i) / (i + 1);
  }
  std::vector<double> d(e.data(), e.data() + e.size());
  const double m = median(d);
  for (double& v : d) v = std::abs(v - m);
  return 1.4826 * median(d) / std::sqrt(binomial);
}

}  // namespace

PresetChoice choose_preset(const Recording& recording) {
  const Dataset d = make_dataset(recording, default_features(), ModelTarget::error);
  if (!d.target.allFinite()) fail(recording.source(), ": no reference rate (ref_rate_dps) to calibrate against");
  if (d.size() < 10) fail(recording.source(), ": ", d.size(), " samples are too few to characterise the noise");
  PresetChoice c;
  c.noise_sigma_dph = units::radps_to_dph(difference_sigma(d.target, 5));
  c.low_order_sigma_dph = units::radps_to_dph(difference_sigma(d.target, 3));
  c.error_rms_dph = units::radps_to_dph(std::sqrt(d.target.squaredNorm() / static_cast<double>(d.size())));
  c.reasons.push_back(str_cat("noise: white ", format_significant(c.noise_sigma_dph, 3), " deg/h per sample from 5th differences of the rate error (",
                              format_significant(c.low_order_sigma_dph, 3), " from 3rd differences; the error's rms is ",
                              format_significant(c.error_rms_dph, 3), " deg/h)"));
  if (c.noise_sigma_dph < 0.5 * c.low_order_sigma_dph || !(c.noise_sigma_dph > 1e-9 * c.error_rms_dph)) {
    c.preset = "builtin:calibration/rbf_noise_free.yaml";
    c.reasons.push_back(str_cat("noise-free (higher differences keep shrinking: what they leave is the surface's curvature, not noise): ", c.preset,
                                " - an interpolating OLS network; with nothing to average out, every node is information"));
  } else {
    c.preset = "builtin:calibration/rbf_noisy.yaml";
    c.reasons.push_back(str_cat("noisy (3rd and 5th differences agree: white noise): ", c.preset,
                                " - the noisy-calibration experiment's best configuration; the evidence decides white or coloured noise"));
  }
  c.request = calibration_request_from_config(ConfigNode::load(c.preset));
  return c;
}

}  // namespace gyrosid
