// Estimating a triad model (model/triad_model.h) from a triad recording - what
// `gyrosid calibrate --model triad` does:
//
//   joint       M, b(T), G and the per-gyro surfaces in one least-squares problem (triad_problem.h), solved
//               by a named back-end (solvers/nls: ceres by default, nlopt, ipopt). Classical surfaces enter
//               linearly. RBF surfaces start from the sequential fit (its selected nodes, its widths, the
//               constant folded into b), keep its weight penalty (the ols fitter's ridge), their share of
//               the columns of b_i and the gauge that splits the scale factor between M_ii and the surface
//               (rbf_diagonal, below; left free, M_ii and b trade against the surface).
//               rbf_joint=weights (default) then moves their weights with M and G: the same functions, one
//               linear least-squares problem started at the sequential solution (which meets every penalty
//               row), so its cost can only fall. The bias polynomials stay the sequential fit's (rbf_bias=held,
//               default for additive surfaces in the mean gauge): M does not act at rest, and left free they
//               took the surfaces' misfit on the turning rows into the static response between the temperature
//               plateaus, which only the ramps measure (FOG triad, one-diagonal training, 20 seeds: long flight
//               joint/sequential 1.21 free, 0.73 held; medium 0.78 and 0.55; README). rbf_bias=free moves them.
//               rbf_joint=nodes moves every centre and width too (the
//               thesis's "misalignment angles posed with the RBF widths, centres and weights"); that freedom
//               fits the training noise where the data are thin - between temperature plateaus - and loses the
//               long flight (experiments/triad_misalignment/README.md).
//   sequential  M, b(T), G first without surfaces; then each gyro's surface fitted to what they leave, by
//               the surface kind's own fitter (solvers/calibrate.h: classical, greybox, rbf with any solver).
//               RBF surfaces with rbf_diagonal=zero_rate then get the second stage described below.
//               Classical surfaces (sequential_scale=triad, default): the second stage is the triad problem
//               with M's off-diagonals and G held at the first stage's and M_ii, b and the surface's
//               coefficients free - the joint fit's parametrisation, M_ii carrying the whole constant scale
//               factor against the reference rate. The classical fitter's own form (sequential_scale=surface)
//               puts a constant scale factor s_0 on the *measured* output beside the first stage's M_ii: its
//               residual is (1 - s_0) times the output residual, so it minimises (1 - s_0)^2 |r|^2, not |r|^2,
//               and moves along the direction where M_ii trades with the odd rate powers (M_ii's joint sigma
//               10-18 ppm, inflation 14) by about N sigma_M^2 (1.6 ppm noise-free on the rate-nonlinear FOG,
//               predicted 1.7): the two fits then differ where the training does not tell them apart.
//               With the same parametrisation the two differ only by the off-diagonals (and G) and agree
//               exactly where the design separates them from the surfaces (Frisch-Waugh-Lovell).
//   auto        both, and the joint fit returned only where a specification test on M rejects the sequential
//               fit's restriction (the surfaces couple with M); else the sequential fit, then the efficient one
//               (auto_estimation.h).
//
// What M_ii carries beside an RBF surface (rbf_diagonal). An additive surface e_i(T, g_i) and M_ii trade along
// a direction the data barely see: the nodes can mimic most of M_ii's column. Something fixes that gauge.
//   mean (default): M_ii is the first stage's mean scale factor over the training turns, and the surface's
//               share of M_ii's column is held at the sequential fit's (owned_column_rows).
//   zero_rate:  M_ii is the zero-rate scale factor (the gain a small-signal test measures), the surface carries
//               the rate dependence: a row holds the surface's slope in its own rate at zero rate, averaged over
//               the training temperatures, at 0 (a slope that varies with temperature stays the surface's). The
//               networks are selected as in the mean gauge; a second stage then fits M_ii, b and the weights in
//               this gauge with the off-diagonals and G held at the first stage's - the sequential result - and
//               the joint fit frees them from there (its cost can only fall). The off-diagonals are then the
//               zero-rate cross gains, which the rows where gyro i is still measure.
// Measured (experiments/triad_misalignment, compare: median criterion of fit of the joint fit, short / medium /
// long, m; zero_rate against mean):
//   rate sweep, 20 seeds: reference FOG triad 0.484 / 0.199 / 3.51e4 against 0.716 / 0.569 / 3.44e4; the
//     rate-linear control 0.0558 / 0.239 / 2.41e4 against 0.0568 / 0.245 / 2.41e4. Joint and sequential tie
//     in every cell (in the mean gauge the joint loses 0.9 % on the FOG's short flight: it puts the factor
//     (1 + M_ii) on the off-diagonals, README).
//   diagonal sweep, 10 seeds: FOG 0.545 / 0.142 / 3.29e4 against 0.555 / 0.334 / 3.13e4; control 0.0485 /
//     0.272 / 2.73e4 against 0.045 / 0.255 / 2.72e4.
//   one diagonal (unbalanced), 10 seeds: FOG 1.02 / 1.53 / 1.09e5 against 0.679 / 0.441 / 8.2e4, and there the
//     joint loses 1.36x to the sequential on long; control 0.0557 / 0.265 / 3.01e4 against 0.0527 / 0.263 / 2.8e4.
// So zero_rate is much the better on the FOG's short and medium flights of balanced programmes and much the worse
// on the unbalanced one; mean stays the default. Selecting the networks with M_ii = 0 (the whole scale factor
// theirs) was worse still (the control 0.147 / 0.431 m on the rate sweep). The row's weight (1e3; measured in
// that variant): noise-free flights agree to 3 digits from 0.01 to 1e4; with noise, weights of 100 and more
// agree and weaker ones let the noise move M_ii.
//
// What an RBF surface models (rbf_form). error (default): the rate error e_i(T, g_i) itself. scale_factor: a
// relative scale-factor error r_i(T, g_i) and the surface e_i = g_i r_i - the classical surface's form with an RBF
// for its polynomials. The network's selection fits r = e / g on the samples where the gyro turns at
// rbf_min_rate_dps or more (the fitter's ridge, chosen on r's heteroscedastic noise, is not carried over); the
// sequential fit then has the classical surfaces' second stage (M_ii, b and the weights, off-diagonals and G held)
// and the joint fit moves the weights of g phi_j with everything. Why: a gyro's gain at small signals (at rest in
// a turn of another axis it outputs the cross term m_ij w_j times that gain) differs from the mean scale factor
// over the turns that M_ii carries by -550 ppm on the reference FOG; a relative network holds that as its value
// r(T, 0), an additive one needs a slope at zero rate its nodes cannot make. The static bias beyond b_i(T) is then
// nobody's: bias_order carries it. Measured (experiments/triad_misalignment, compare, 20 seeds; width 0.6, since
// turns come only at plateaus 40 C apart; joint medians short / medium / long, m, scale_factor against error):
//   rate sweep:     FOG 0.127 / 0.122 / 2.92e4 against 0.716 / 0.569 / 3.44e4; control 0.0659 / 0.0845 / 2.46e4
//                   against 0.0568 / 0.245 / 2.41e4;
//   diagonal sweep: FOG 0.22 / 0.147 / 3.43e4 against 0.561 / 0.362 / 3.13e4; control 0.0578 / 0.091 / 2.49e4
//                   against 0.0464 / 0.23 / 3.05e4;
//   one diagonal:   FOG 0.459 / 0.423 / 1.29e5 against 0.678 / 0.441 / 8.67e4 (its joint fit loses to its
//                   sequential 1.4x / 2.0x / 1.8x); control 0.069 / 0.0989 / 2.42e4 against 0.0527 / 0.249 / 2.77e4.
// So it is the better form on balanced programmes' medium flights (3-4x) and the FOG's short ones, the worse on the
// unbalanced programme's FOG; error stays the default.
//
// The surfaces' rate input while fitting (surface_input). Fitted at the *recorded* output (measured), every
// surface column carries the very noise its row fits: errors in variables. A rate polynomial then spends its
// weakly determined combinations - those that vanish at the training rates - on that noise and swings between
// the training rates (rate-linear triad on triad_rate_sweep.yaml, sf_rate_order 6, 10 deg/h: 0.1..1.7 deg/h at
// 10..80 deg/s, differently in joint and sequential fits of the same data, which so parted on the flights).
// smoothed (default) fits them at each output with its white noise averaged down where the reference holds
// still (a centred window of surface_window samples each side, inside a rate step or hold, the sample itself
// left out; smoothed_outputs in triad_fit.cpp); noise-free it is the recorded output to second order in the temperature drift. The model's
// own prediction is no substitute: it replaces the noise by the model's misfit (tried: noise-free fits of the
// rate-nonlinear FOG moved, medium-flight error 0.48 -> 0.63 m).
//
// Before each solve the entries the data do not determine are found (nls_covariance.h) and held at their
// nominal value 0; they are reported as not determined, never as measured. Priority goes to M, then b, G and
// the surfaces: a surface coefficient the data cannot tell from M_ii (a rate shape seen at one rate only) is
// the one held, with a note. Sigmas come from the covariance
// at the solution with each gyro's noise level estimated from its own residuals; M and G entries whose sigma
// exceeds max_sigma are likewise reported as not determined.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/solve_summary.h"
#include "model/triad_angles.h"
#include "model/triad_model.h"
#include "solvers/common/options.h"
#include "solvers/triad/hold_stillness.h"

namespace gyrosid {

struct TriadFitOptions {
  std::string surfaces = "none";      // none | classical | greybox | rbf
  std::string estimation = "joint";   // joint | sequential | auto (both, the joint returned where a test rejects
                                      // the sequential fit's restriction: auto_estimation.h)
  double coupling_test_level = 0.01;  // estimation=auto: the test's level
  std::string solver = "ceres";       // a solvers/nls back-end: ceres | nlopt | ipopt
  OptionMap solver_options;           // nls.<key>=<value>
  int bias_order = 2;                 // b_i(T) polynomial order (reduced to 0 when the temperature is constant)
  bool g_sensitivity = false;         // estimate G (needs accel_{x,y,z}_mps2)
  std::string reference = "auto";     // rate | angle | auto (angle when the metadata say "reference: angle")
  double max_sigma = 0.01;            // M, G entries with a larger sigma are reported as not determined
  double collinearity = 1e-2;         // a surface coefficient within this sine of the span of M, b, G is held
                                      // at nominal (it would inflate their sigmas ~1/collinearity)
  std::string surface_solver = "ols"; // rbf surfaces: the RBF solver of the sequential fit / joint start
  std::string rbf_joint = "weights";  // joint rbf: weights (centres, widths held) | nodes (everything moves)
  std::string rbf_diagonal = "mean";  // rbf surfaces: what M_ii carries, mean | zero_rate (below)
  std::string rbf_bias = "held";      // joint rbf surfaces: the bias polynomials held at the sequential fit's | free (below)
  std::string rbf_form = "error";     // rbf surfaces: error e_i(T, g) | scale_factor e_i = g r_i(T, g) (below)
  double rbf_min_rate_dps = 1.0;      // rbf_form=scale_factor: r is fitted where |g| >= this
  std::string sequential_scale = "triad";  // sequential classical: who carries the constant scale factor (below)
  std::string surface_input = "smoothed";  // the rate the surfaces are fitted at: smoothed | measured (below)
  int surface_window = 30;                  // smoothed: half-width of the centred window, samples
  OptionMap surface_options;          // surface.<key>=<value>: options of the surface kind or its solver;
                                      // classical surfaces without sf_rate_order / sf_cross_order: auto (fit_triad)
  // How surface.sf_rate_order=auto / sf_cross_order=auto choose among the fitted orders 0..top (fit_triad):
  //   bic     the lowest BIC: for the parameters, consistent when the family holds the sensor;
  //   aic     the lowest AIC: for the flights, efficient prediction when no order holds it (a FOG's ripple);
  //   bic_lr  (the default) BIC's order b, unless a likelihood-ratio test against the top order rejects it:
  //           then the lowest order o >= b that the test does not reject at level order_test_level,
  //             Lambda_o = (-2 ln L_o) - (-2 ln L_top) ~ chi^2(k_top - k_o) if order o holds the sensor (Wilks).
  //           Where the family at b holds the sensor, b (rejected at rate order_test_level); where the data show
  //           the lack of fit BIC's ln(3R) per parameter outweighs, the order that removes it.
  std::string order_criterion = "bic_lr";
  double order_test_level = 0.01;  // bic_lr: the test's level (probability of raising a correct order)
  OptionTable table();
  std::string validate() const;
};

struct TriadUncertainty {
  Eigen::Matrix3d misalignment_sigma = Eigen::Matrix3d::Constant(NAN);
  Eigen::Matrix3d misalignment_inflation = Eigen::Matrix3d::Constant(NAN);
  std::array<std::array<bool, 3>, 3> misalignment_known{};  // determined by the data
  // Covariance of vec(M) (entry 3 i + j): NaN for entries not estimated, and between entries estimated in
  // different stages (a sequential fit's M_ii and off-diagonals).
  Eigen::Matrix<double, 9, 9> misalignment_covariance = Eigen::Matrix<double, 9, 9>::Constant(NAN);
  std::array<Eigen::VectorXd, 3> bias_sigma;               // per coefficient, rad/s
  std::array<std::vector<bool>, 3> bias_known;
  std::optional<Eigen::Matrix3d> g_sensitivity_sigma;
  std::array<std::array<bool, 3>, 3> g_sensitivity_known{};
  std::array<double, 3> noise_radps{};  // each gyro's residual standard deviation (per row)
};

// The fit's Bayesian information criterion (Schwarz), one definition for surface.sf_cross_order=auto and for the
// model file (summary.details.information_criterion): each gyro's R rows Gaussian with their own variance at its
// maximum-likelihood value rss_i / R, k the parameters the fit estimated,
//   BIC = sum_i R ln(rss_i / R) + k ln(3 R),   rss_i in (rad/s)^2,
// i.e. -2 ln L + k ln n up to a constant that depends on R only. k counts the free entries of the final problem,
// plus, for the sequential classical fit, the off-diagonals and G its first stage estimated and its second held,
// and a classical surface fitted by its own fitter (sequential_scale=surface) by its coefficients. NaN where the
// fit's parameters are not all counted that way (greybox or rbf surfaces fitted by their own fitter) or where
// not every residual is a row (reference=gravity: the turns' residuals).
// Akaike's criterion from the same likelihood, AIC = sum_i R ln(rss_i / R) + 2 k, for order_criterion=aic; the
// likelihood itself for order_criterion=bic_lr's test.
struct TriadInformationCriterion {
  int rows_per_gyro = 0;              // R
  int parameters = 0;                 // k
  std::array<double, 3> rss_radps2{}; // per gyro, over its rows (weighted as the rows are), the surfaces at the
                                      // input they were fitted at (surface_input)
  double minus_2_ln_l = NAN;         // sum_i R ln(rss_i / R): -2 ln L up to a constant that depends on R only
  double bic = NAN;
  double aic = NAN;
};

struct TriadFit {
  TriadModel model;
  TriadUncertainty uncertainty;
  AngleObservability angles;
  std::vector<std::string> notes;   // what was not determined, and why
  std::string reference;            // how the rows were formed
  std::array<double, 3> residual_rms_dph{};  // per gyro, of the final fit's rows (surfaces at their fitting input)
  std::array<double, 3> noise_density{};     // white-noise density rad/s/sqrt(Hz) (= N, ARW) from the residuals
  double sample_rate_hz = 0.0;               // median sampling rate of the recording
  HoldStillnessCheck hold_stillness;         // reference=gravity: the holds checked for stillness (hold_stillness.h)
  TriadInformationCriterion criterion;
  SolveSummary summary;             // the final solve; details["stages"] holds every stage's summary,
                                    // details["information_criterion"] the criterion above
  TriadFitOptions options;
  std::string estimation_chosen;    // estimation=auto: the fit it returned, joint or sequential (auto_estimation.h)
};

TriadFit fit_triad(const TriadData& data, const TriadFitOptions& options, const std::string& reference_metadata = "");

// How the fit's rows are formed: options.reference, or for reference=auto the recording's metadata 'reference'
// (angle, gravity; anything else: rate).
std::string triad_reference_mode(const TriadFitOptions& options, const std::string& reference_metadata);

}  // namespace gyrosid
