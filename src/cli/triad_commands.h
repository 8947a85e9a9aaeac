// The triad paths of calibrate, compensate and export (a triad model is not a single-gyro model).
#pragma once

#include <string>
#include <vector>

namespace gyrosid::cli {

struct TriadCalibrateRequest {
  std::string recording, out, solver, surfaces, estimation;
  std::vector<std::string> set;  // key=value (triad options, nls.*, surface.*)
};
void calibrate_triad(const TriadCalibrateRequest& request);
std::string triad_help();  // the triad's options and the nls back-ends'

}  // namespace gyrosid::cli
