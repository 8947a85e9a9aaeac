// Outputs of `gyrosid explain` (the contract outside tools read): explain.json, residuals.csv
// (t_s,residual_before_dph,residual_after_dph,heldout: 0 training, 1 held out, 2 held out outside the
// training support; heldout_scored: 1 on exactly the rows the held-out proof scores), model.json (loadable
// by every command) and
// report.md with its plots - residual in time before and after, residual over (T, omega) split into heating
// and cooling, correlation with every channel, Allan deviation of the residual against its noise terms.
#pragma once

#include <filesystem>

#include "explain/explain.h"

namespace gyrosid {

void write_explain_outputs(const explain::ExplainResult& result, const std::filesystem::path& dir);

}  // namespace gyrosid
