// Which of the twelve physical angles of a triad's misalignment chain (thesis s3.4: per gyro two IA->RA
// angles and two insertion angles, IA -> RA -> CA -> B) a calibration determines. To first order the
// measurement matrix depends on them only through six sums (eq 3.72), e.g. M_xy = phi_y + mu_y: no angle is
// observable by itself, and a sum only when its matrix entry is. The map is the derivative of the exact
// chain (sensor/misalignment.h) at zero angles, so it follows the simulator's conventions by construction.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace gyrosid {

struct AngleObservability {
  struct Combination {
    std::string entry;       // "M_xy": row x (gyro x), column y (body y)
    std::string expression;  // "phi_y + mu_y"
    bool observable = false;
  };
  std::vector<std::string> angles;      // the twelve, gyro x first
  std::vector<bool> angle_observable;   // each angle alone
  std::vector<Combination> combinations;  // one per off-diagonal entry of M
  int rank = 0;                           // independent observable combinations
};

// `entry_known[i][j]`: whether the calibration determined M_ij.
AngleObservability analyse_angles(const std::array<std::array<bool, 3>, 3>& entry_known);

}  // namespace gyrosid
