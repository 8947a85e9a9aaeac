// Outputs of a criterion-of-fit evaluation: cof.json and the plots - ground track, position-error growth
// (compensated against uncompensated) and the Monte Carlo histograms of the error components.
#pragma once

#include <filesystem>

#include "nav/cof_report.h"

namespace gyrosid {

void write_cof_outputs(const nav::CofReport& report, const std::filesystem::path& dir);

}  // namespace gyrosid
