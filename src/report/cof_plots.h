// Outputs of a criterion-of-fit evaluation: cof.json and the plots - ground track, position-error growth
// (compensated against uncompensated) and the Monte Carlo histograms of the error components.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "nav/cof_report.h"

namespace gyrosid {

void write_cof_outputs(const nav::CofReport& report, const std::filesystem::path& dir);

// Position-error growth of several runs on one flight, log scale (runs need recorded growth).
void plot_error_growth(const std::filesystem::path& png, const std::string& title,
                       const std::vector<std::pair<std::string, const nav::CofRun*>>& runs);

}  // namespace gyrosid
