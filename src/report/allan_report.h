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

}  // namespace gyrosid
