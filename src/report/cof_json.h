// cof.json: the one writer of a criterion-of-fit result (the contract of `gyrosid cof`; the main job embeds
// the same object per flight).
#pragma once

#include <nlohmann/json.hpp>

#include "nav/cof_report.h"

namespace gyrosid {

nlohmann::json cof_json(const nav::CofReport& report);

}  // namespace gyrosid
