// The coordinates a grey-box unit is compared in across units, and a Gaussian prior over them - what a
// production lot (src/lot/) learns and `calibrate --prior` fits a new unit with.
//
// A fit's coefficients are scaled to its own recording (TermScaling::of): two units' coefficient vectors are
// not comparable. The coordinates theta are physical and the same for every recording of a structure:
//   bias    b(T_j) in deg/h at bias_order + 1 temperatures T_j spread evenly over the surface grid's range
//           (the polynomial's values: an invertible linear map of its coefficients, eq 3.48's D_F + D_T);
//   surface dSF at every node of the (T, omega) grid, ppm (the surface's own coefficients);
//   shupe   k_S in deg/h per (deg C/min); asymmetry a in ppm; g-sensitivity in deg/h per (m/s^2);
//   lag     the coil's thermal lag tau in s (with thermal_lag).
// Every coordinate but the lag is linear in the fit's coefficients, so a Gaussian prior on theta is a
// Gaussian prior on them (greybox_fit.h fits the maximum a posteriori).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "model/greybox_fit.h"

namespace gyrosid {

struct GreyboxCoordinate {
  std::string name;   // "bias(20 C)", "dSF(40 C, -60 dps)", "shupe", ...
  std::string group;  // bias, surface, shupe, asymmetry, g_sensitivity, lag
  std::string unit;   // dph, ppm, dph_per_c_per_min, dph_per_mps2, s
  double temp_c = 0.0, rate_dps = 0.0;  // where on the (T, omega) plane (bias: T only; others: 0)
};

// The structure must have the surface form (a polynomial scale factor has no grid to compare units on).
std::vector<GreyboxCoordinate> greybox_coordinates(const GreyboxOptions& options);
std::vector<double> greybox_bias_nodes_c(const GreyboxOptions& options);
// theta's coordinates as named spans, in greybox_coordinates' order; absent parts have size 0.
struct GreyboxThetaLayout {
  explicit GreyboxThetaLayout(const GreyboxOptions& options);
  Span bias, surface, shupe, asymmetry, g_sensitivity, lag;  // surface: the grid's nodes, temperature-major
  Eigen::Index size = 0;
};
// theta of a grey-box error model and lag (the lag last when the structure has one).
Eigen::VectorXd greybox_theta(const GyroErrorModel& errors, double lag_tau_s, const GreyboxOptions& options);

// theta's linear part (every coordinate but the lag) as a matrix on a fit's coefficients, in greybox_terms'
// order and scaled by `scaling` (physics_terms.h): theta_lin = M c. Square: as many coordinates as coefficients.
Eigen::MatrixXd greybox_theta_map(const GreyboxOptions& options, const TermScaling& scaling);

// A Gaussian prior N(mean, covariance) over greybox_coordinates(options).
struct GreyboxPrior {
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;  // symmetric positive definite
  std::string source;          // where it was learned (a lot file), for the summary
  std::string validate(const GreyboxOptions& options) const;
};

}  // namespace gyrosid
