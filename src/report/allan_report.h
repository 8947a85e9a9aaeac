// Allan analysis of a rate written to a directory: allan.csv (the curve with confidence intervals),
// allan.json (the IEEE Std 952 noise coefficients, with provenance) and allan.png (curve and fitted lines).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sensor/allan.h"

namespace gyrosid {

struct AllanReport {
  std::vector<AllanPoint> curve;  // deg/h
  AllanCoefficients fit;          // deg/h-based units
};

AllanReport write_allan(const std::filesystem::path& dir, const std::vector<double>& rate_dph, double dt_s,
                        const AllanOptions& options, const std::string& title, nlohmann::json provenance);

// A Kalibr-style IMU noise file (imu.yaml) with the gyro terms of an Allan fit in the continuous-time units
// Kalibr expects - the conversion written beside each number:
//   gyroscope_noise_density [rad/s/sqrt(Hz)] = N [deg/sqrt(h)] * (pi/180) / 60          (angle random walk)
//   gyroscope_random_walk   [rad/s^2/sqrt(Hz)] = K [(deg/h)/sqrt(h)] * (pi/180) / 3600 / 60   (rate random walk)
// They are densities, not per-sample sigmas: the discrete white-noise sigma at rate f is density * sqrt(f),
// the discrete bias step density / sqrt(f) - the confusion most reported against Kalibr and
// allan_variance_ros. The accelerometer lines are left out (a gyro recording says nothing about them).
void write_kalibr_noise_yaml(const std::filesystem::path& path, const AllanCoefficients& fit, double update_rate_hz,
                             const std::string& source);

}  // namespace gyrosid
