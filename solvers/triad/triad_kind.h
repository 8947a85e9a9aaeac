// The triad as an entry of model_fitters() (solvers/calibrate.h): `gyrosid calibrate --model triad`, Python's
// calibrate(model="triad"). Its options are TriadFitOptions' --set keys (surfaces, estimation, solver, nls.*,
// surface.*); --solver names the least-squares back-end. Its file is triad_file.h's: the model's values with the
// fit's sigmas and observability beside them.
#pragma once

#include <memory>
#include <string>

#include "solvers/calibrate.h"

namespace gyrosid {

std::unique_ptr<ModelFitter> triad_fitter(const CalibrationRequest& request);
std::string triad_help();  // the triad's options and the least-squares back-ends'

}  // namespace gyrosid
