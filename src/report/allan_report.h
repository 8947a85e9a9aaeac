// Allan analysis of a rate written to a directory: allan.csv (the curve with confidence intervals and the
// fitted total), allan.json (the identified noise model - every term with its interval, the band of taus the
// fit claims, what was left out and why, where the model misses the data - with provenance) and allan.png
// (curve, band, fitted total with its band, each term).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "noise/allan.h"
#include "noise/identify.h"

namespace gyrosid {

struct AllanReport {
  std::vector<AllanPoint> curve;     // deg/h
  NoiseIdentification noise;         // deg/h-based units
  // Taus inside the fit band where the fitted deviation lies outside the data's confidence band.
  std::vector<double> outside_band_tau_s;
  std::string outside_band_note;  // the same in a sentence; empty when none
};

// Terms in the units people quote: Q arcsec, N deg/sqrt(h), B deg/h, K (deg/h)/sqrt(h), R (deg/h)/h, GM sigma
// deg/h and tau s - from the deg/h-based units of an identification (Q (deg/h) s, N (deg/h) sqrt(s), ...).
struct QuotedTerm {
  std::string name, meaning, unit;
  double value = 0.0, sigma = 0.0, low = 0.0, high = 0.0;
};
std::vector<QuotedTerm> quoted_terms(const NoiseIdentification& noise);

AllanReport write_allan(const std::filesystem::path& dir, const std::vector<double>& rate_dph, double dt_s, const AllanOptions& options,
                        const NoiseIdOptions& noise_options, const std::string& title, nlohmann::json provenance);

// The identified model an allan.json holds (in deg/h-based units), for commands that take a measured noise
// in place of a sensor config's (design --noise). Errors name the file and the key.
CompositeNoise load_identified_noise(const std::filesystem::path& allan_json);

// A Kalibr-style IMU noise file (imu.yaml) with the gyro terms of an identified model in the continuous-time
// units Kalibr expects - the conversion written beside each number:
//   gyroscope_noise_density [rad/s/sqrt(Hz)] = N [deg/sqrt(h)] * (pi/180) / 60          (angle random walk)
//   gyroscope_random_walk   [rad/s^2/sqrt(Hz)] = K [(deg/h)/sqrt(h)] * (pi/180) / 3600 / 60   (rate random walk)
// They are densities, not per-sample sigmas: the discrete white-noise sigma at rate f is density * sqrt(f),
// the discrete bias step density / sqrt(f) - the confusion most reported against Kalibr and
// allan_variance_ros. Kalibr has no flicker or Gauss-Markov term: those are named in a comment. The
// accelerometer lines are left out (a gyro recording says nothing about them).
void write_kalibr_noise_yaml(const std::filesystem::path& path, const CompositeNoise& model_dph, double update_rate_hz,
                             const std::string& source);

}  // namespace gyrosid
