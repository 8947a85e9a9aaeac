// Presets chosen from the data (issue 11): what `gyrosid calibrate` does when given a recording and no
// model, solver, options or config. It characterises the recording's noise and picks the built-in
// calibration preset for it, saying what it measured and why:
//
//   noise estimate   s_k = 1.4826 MAD(k-th differences of the rate error) / sqrt(C(2k, k)), per sample, for
//                    k = 3 and 5: white noise passes through k-th differences with variance C(2k, k) sigma^2,
//                    so s_3 = s_5 = sigma; a smooth error surface along the trajectory is removed more and
//                    more by higher differences, so without noise s_5 falls well below s_3
//   noise-free       s_5 < s_3 / 2 (what the differences leave keeps shrinking with the order: signal, not
//                    noise): builtin:calibration/rbf_noise_free.yaml (an interpolating OLS network - nothing
//                    to average out, every node is information)
//   noisy            builtin:calibration/rbf_noisy.yaml, the experiment's best configuration for noisy data
//                    (experiments/noisy_calibration); its noise=auto then decides by the evidence whether the
//                    noise is white or coloured (white + random walk + Gauss-Markov, Kalman-whitened) and the
//                    solve summary's details say which and why.
#pragma once

#include <string>
#include <vector>

#include "core/recording.h"
#include "solvers/calibrate.h"

namespace gyrosid {

struct PresetChoice {
  std::string preset;                 // builtin:calibration/<name>.yaml
  CalibrationRequest request;         // as read from the preset
  double noise_sigma_dph = 0.0;       // s_5, per sample
  double low_order_sigma_dph = 0.0;   // s_3
  double error_rms_dph = 0.0;         // rms of the rate error (gyro - reference)
  std::vector<std::string> reasons;   // what was measured and why the preset fits it, one line each
};

PresetChoice choose_preset(const Recording& recording);

}  // namespace gyrosid
