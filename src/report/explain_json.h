// explain.json: the one place an explain result (explain/explain_result.h) is written as JSON and read back.
// Outside tools read this file; its keys are the contract.
#pragma once

#include <nlohmann/json.hpp>

#include "explain/explain_result.h"

namespace gyrosid {

nlohmann::json to_json(const explain::ExplainSummary& summary);
// Reads what to_json wrote (the diagnostics' lag curves and Allan points are not in the file).
explain::ExplainSummary explain_summary_from_json(const nlohmann::json& j);

}  // namespace gyrosid
