// Statistics for Monte Carlo evaluation (thesis s5.5): the Anderson-Darling test for normality with mean
// and variance estimated from the sample (Stephens 1974; D'Agostino & Stephens 1986, s4.8, case 3):
//   A^2 = -n - (1/n) sum_{i=1..n} (2i - 1) [ln Phi(z_(i)) + ln(1 - Phi(z_(n+1-i)))],  z = (x - mean)/s
//   A*^2 = A^2 (1 + 0.75/n + 2.25/n^2);   normal at 5 % when A*^2 < 0.752
// with the p-value approximation of D'Agostino & Stephens Table 4.9.
#pragma once

#include <vector>

namespace gyrosid::nav {

struct AndersonDarling {
  double a2 = 0.0;
  double a2_adjusted = 0.0;  // A*^2
  double p_value = 0.0;
  bool normal_at_5_percent = false;
};

AndersonDarling anderson_darling_normal(std::vector<double> sample);

struct SampleStats {
  double mean = 0.0, sigma = 0.0;  // sigma with n - 1
};
SampleStats sample_stats(const std::vector<double>& x);

}  // namespace gyrosid::nav
