// Fitting the grey-box model (greybox_model.h) to a recording. Given the coil's lag tau every coefficient is
// linear: the model's structure is a list of physics terms (physics_terms.h - the same columns explain
// uses), fitted in the forward direction (the physics is defined on the true rate) by column-pivoted QR on
// unit-norm columns with a small ridge. The lag is nonlinear: a coarse log grid of tau (the residual in tau
// can have several dips), then NLopt's BOBYQA on log tau from the best point; tau = 0 stays a candidate.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "core/packed_layout.h"
#include "core/solve_summary.h"
#include "model/greybox_model.h"
#include "model/physics_terms.h"

namespace gyrosid {

enum class ScaleFactorForm { surface, polynomial };

template <>
struct EnumNames<ScaleFactorForm> {
  static constexpr std::string_view kNoun = "scale-factor form";
  static constexpr std::array<std::pair<ScaleFactorForm, std::string_view>, 2> kTable{
      {{ScaleFactorForm::surface, "surface"}, {ScaleFactorForm::polynomial, "polynomial"}}};
};

struct GreyboxOptions {
  int bias_order = 3;
  ScaleFactorForm scale_factor = ScaleFactorForm::surface;
  std::vector<double> surface_temperatures_c{-20, 0, 20, 25, 40, 60};  // the thesis grid
  std::vector<double> surface_rates_dps{-100, -80, -60, -40, -20, -10, 10, 20, 40, 60, 80, 100};
  int sf_temperature_order = 2;
  int sf_rate_order = 6;
  bool shupe = false;
  bool asymmetry = false;
  bool g_sensitivity = false;
  bool thermal_lag = false;
  double lag_max_s = 3600.0;
  double ridge = 1e-9;  // relative to the scaled normal-matrix norm, for grid cells the data never visits
  std::string validate() const;
};

// Features: measured_rate, temperature (+ accel_x_mps2, accel_y_mps2, accel_z_mps2 for g-sensitivity).
std::vector<std::string> greybox_features(const GreyboxOptions& options);
// The model's structure as physics terms, in the order of its coefficients.
std::vector<Term> greybox_terms(const GreyboxOptions& options);

// greybox_terms' coefficients as named spans: the bias polynomial (constant first), then the scale factor
// (separable: eps_T's orders 1.. and eps(omega)'s orders 0..; surface: the grid's nodes, temperature-major),
// Shupe, asymmetry, g-sensitivity (x, y, z). Absent parts have size 0.
struct GreyboxCoefficients {
  explicit GreyboxCoefficients(const GreyboxOptions& options);
  Span bias, sf_temperature, sf_rate, surface, shupe, asymmetry, g_sensitivity;
  Eigen::Index size = 0;
};

// The summary's details: samples, parameters, rms_residual_dph, lag_tau_s, lag_evaluations. Its
// termination is the lag search's (NLopt's code, or no_progress when it stopped on round-off with its best
// point); a fit without a lag is one linear solve (converged).
std::unique_ptr<GreyboxModel> fit_greybox(const Dataset& data, const GreyboxOptions& options, SolveSummary* summary = nullptr);

struct GreyboxPrior;  // greybox_prior.h

// A fit with what a lot needs of it: the unit's coordinates theta (greybox_prior.h) and their covariance.
struct GreyboxEstimate {
  std::unique_ptr<GreyboxModel> model;
  Eigen::VectorXd theta;             // greybox_theta of the model
  Eigen::MatrixXd theta_covariance;  // of the estimate, from the linear solve at the found lag (the lag's row: 0)
  double residual_sd_radps = 0.0;    // per sample: sqrt(RSS / (n - p)) of the fit without a prior
};

// With a prior N(mu, Sigma) over theta, the maximum a posteriori: with Sigma_c = L L' the prior of theta's
// linear part (theta_c = M c),
//   c = argmin |A c - y|^2 / s^2 + |L^-1 (M c - mu_c)|^2,   + (tau - mu_tau)^2 / var_tau in the lag search,
// solved by Householder QR of the stacked rows [A / s; L^-1 M] on unit-norm columns (no ridge: the prior
// makes it full rank). s is the residual sd of the fit without the prior at the prior's mean lag: the
// recording's noise as white (coloured noise makes it trust the data more than it should, never less).
// Where the recording determines a coordinate the data win; where it does not, the prior fills in. The
// summary adds data_share per group: 1 - (posterior variance / prior variance), averaged over the group's
// coordinates (1: the recording alone, 0: the prior alone). The model carries the posterior of its
// coefficients at the found lag (GreyboxPosterior: covariance (S'S)^-1 from the same QR's R factor, noise s),
// so predict_with_sigma works for it, and the summary adds predictive_sigma: its rms and maximum (deg/h) over
// the surface grid's nodes and where the maximum is. Without a prior: fit_greybox's solve, no posterior.
GreyboxEstimate estimate_greybox(const Dataset& data, const GreyboxOptions& options, const GreyboxPrior* prior,
                                 SolveSummary* summary = nullptr);

}  // namespace gyrosid
