// The files of `gyrosid lot screen` (pipeline/lot_jobs.h): each unit's screen.json and, for several units,
// screens.csv with a row per unit.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lot/screen.h"

namespace gyrosid {

// Each unit's directory: `out` for one recording; for several, out/<its path from the recordings' common
// folder, without the extension> (units/a.csv -> a/, lot/u0007/short.csv -> u0007/short/). Error when two
// recordings would share one.
std::vector<std::filesystem::path> screen_dirs(const std::filesystem::path& out, const std::vector<std::string>& recordings);

// screen.json: the result, the recording, the lot file, alpha and the unit's white noise.
nlohmann::json screen_json(const ScreenResult& result, const std::string& recording, const std::string& prior, double alpha,
                           double white_dph_at_1hz);

// A row of screens.csv (its header: kScreensCsvHeader).
inline constexpr const char* kScreensCsvHeader = "recording,out_of_family,p_value,p_physics,p_noise,white_dph_at_1hz,first_reason\n";
std::string screens_csv_row(const ScreenResult& result, const std::string& recording, double white_dph_at_1hz);

}  // namespace gyrosid
