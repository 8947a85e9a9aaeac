// A unit as the lot sees it (lot_model.h): calibrated with the lot's grey-box structure from its recording -
// its coordinates, their covariance and its white noise - or read from a calibrated model file (its
// coordinates only: a model file keeps no covariance and no noise).
#pragma once

#include <string>

#include "core/recording.h"
#include "core/solve_summary.h"
#include "lot/lot_model.h"
#include "model/greybox_model.h"

namespace gyrosid {

// White noise: noise/identify.h (the one noise estimator) on the fit's residual in deg/h; its N term, or,
// where the identified structure has none, the residual's sd per sample times sqrt(dt).
LotUnit calibrate_unit(const Recording& recording, const std::string& name, const GreyboxOptions& structure,
                       SolveSummary* summary = nullptr);

LotUnit unit_of_model(const GreyboxModel& model, const std::string& name, const GreyboxOptions& structure);

}  // namespace gyrosid
