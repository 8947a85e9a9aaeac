// Test helper: the log relative error, NIST StRD's accuracy measure, -log10(|estimate - certified| / |certified|):
// the number of significant digits an estimate shares with the certified value (15 when they are equal).
#pragma once

#include <cmath>

namespace gyrosid::testing_support {

inline double lre(double estimate, double certified) {
  const double rel = std::abs(estimate - certified) / std::abs(certified);
  return rel == 0 ? 15.0 : -std::log10(rel);
}

}  // namespace gyrosid::testing_support
