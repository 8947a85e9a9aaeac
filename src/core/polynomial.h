// A polynomial about a reference point, p(x) = sum_i c_i (x - x0)^i, evaluated by Horner's rule.
#pragma once

#include <vector>

namespace gyrosid {

struct Polynomial {
  std::vector<double> coefficients;  // c_0, c_1, ... (empty = zero polynomial)
  double reference = 0.0;            // x0

  double operator()(double x) const {
    double value = 0.0;
    const double u = x - reference;
    for (auto it = coefficients.rbegin(); it != coefficients.rend(); ++it) value = value * u + *it;
    return value;
  }
  double derivative(double x) const {
    double value = 0.0;
    const double u = x - reference;
    for (std::size_t i = coefficients.size(); i-- > 1;) value = value * u + static_cast<double>(i) * coefficients[i];
    return value;
  }
  bool empty() const { return coefficients.empty(); }
};

}  // namespace gyrosid
