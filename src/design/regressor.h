// The calibration model a design is for, as a model linear in its parameters theta around its expected
// fit: rate error = A(inputs) theta. Exact for the classical polynomial model and the grey-box model at a
// fixed thermal lag (both are linear least squares), a first-order expansion for the grey-box lag, and a
// fixed dictionary of Gaussian nodes for the RBF network (its selection is not linear; issue 11's Bayesian
// posterior replaces this proxy when it lands).
//
//   classical  b(T) + (s_T(T) + s_w(w)) w, thesis s5.3.2 (model/classical_model.h) - physics terms bias,
//              bias_temperature 1..3, scale_factor (1,0),(2,0),(0,0..6)
//   greybox    bias cubic in the coil temperature, scale factor as a bicubic surface on a (T, w) grid
//              spanning the domain (thesis eq 3.48), and the effects whose separation a design must buy:
//              Shupe k_S dT/dt (eq 3.3), hysteresis +-1/2 by heating/cooling branch, and the coil's thermal
//              lag tau behind the probe, linearised: d error / d tau = (d error / d T) (d T_coil / d tau)
//   rbf        sum_j w_j exp(-|x~ - c_j|^2 / r^2) + b on range-normalised (w, T): a grid of nodes over the
//              domain with the normalised width of configs/calibration/rbf_noisy.yaml
//   hybrid     gyrosid's best noisy calibration (model/hybrid_model.h, configs/calibration/rbf_noisy.yaml):
//              the physics b(T) cubic + w dT^i u^j (i <= 2, j <= 3) with a flat prior, plus the rbf dictionary
//              (no constant) with a Gaussian prior - the Bayesian network on what the physics leaves; a
//              prediction takes instead the nodes, widths and prior the calibration's evidence would choose
//              along the trajectory (evidence_network.h; option model.network)
//
// Columns use the scaling of the design domain, not of the data, so every trajectory is judged in the same
// parametrisation.
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "design/evidence_network.h"
#include "design/information.h"
#include "model/greybox_fit.h"
#include "model/greybox_prior.h"
#include "model/physics_terms.h"
#include "sensor/gyro_error_model.h"
#include "solvers/common/options.h"

namespace gyrosid::design {

enum class ModelFamily { rbf, greybox, classical, hybrid };

// The (T, w) region a calibration must cover: the application envelope's, with margins.
struct Domain {
  double temp_min_c = -20.0, temp_max_c = 60.0;
  double rate_max_radps = 1.7453292519943295;  // 100 deg/s
  std::string validate() const;
};

struct ModelOptions {
  // rbf: nodes per input and the node width in range-normalised units ([-1, 1] over the domain)
  int rbf_temperature_nodes = 9, rbf_rate_nodes = 9;
  double rbf_width = 0.25;
  // greybox: bias order, surface grid (temperatures evenly over the domain; rates in deg/s within it), effects
  int bias_order = 3;
  int grid_temperatures = 6;
  std::string grid_temperatures_c;  // explicit grid temperatures, comma-separated (overrides the even grid)
  std::string grid_rates_dps = "-100,-80,-60,-40,-20,-10,10,20,40,60,80,100";
  bool shupe = false, hysteresis = false, thermal_lag = false;  // `--criterion effects` turns all on
  // Prior standard deviations of the effects (the others scale with the sensor's error surface).
  double shupe_prior_dph_per_c_per_min = 1.0, hysteresis_prior_dph = 2.0, thermal_lag_prior_s = 300.0;
  // classical: the thesis's orders (configs/calibration/classical.yaml)
  int classical_bias_order = 3, classical_sf_temperature_order = 2, classical_sf_rate_order = 6;
  // hybrid: its physics' scale-factor orders (solvers/bayes/hybrid_fit.h; bias: bias_order) and the network
  // from the rbf options
  int hybrid_sf_temperature_order = 2, hybrid_sf_rate_order = 3;
  // hybrid: the network's prior standard deviation as a multiple of what the physics leaves of the sensor's
  // error over the domain (assessment.cpp, prior_scales)
  double network_prior_scale = 1.0;
  // hybrid: the network a prediction (design.json's `predicted`, --evaluate) is made with: `evidence`, the
  // nodes, widths and prior the calibration would choose along that trajectory (evidence_network.h), or
  // `dictionary`, the fixed dictionary above (what the optimiser's objective uses in either case)
  std::string network = "evidence";
  // hybrid: the dictionary's prior in the optimiser's objective: `residual`, one scale from what the physics
  // leaves of the sensor's error over the domain (above), or `evidence`, the precision alpha the expected
  // evidence gives the dictionary on each candidate's own noise-free target (evidence_network.h): the prior
  // follows each trajectory, as the calibration's does
  std::string network_prior = "residual";
  int network_nodes = 200;  // evidence: centres among the trajectory's inputs (the calibration's `nodes`)
  // network=evidence with the network's hyperparameters given instead of searched (e.g. a fitted model.json's
  // summary: `width`, and its prior sd): the widths (rate, temperature; normalised as the calibration's) and the
  // weights' prior sd in deg/h. Empty / 0: by the expected evidence.
  std::string network_widths;
  double network_prior_sd_dph = 0.0;
  // greybox: the prior the calibration fits with (`calibrate --prior lot.json`, model/greybox_fit.h: a lot's
  // population over greybox_coordinates); null: none, the fit is plain least squares. Not an option key:
  // `design --prior` sets it from a lot file, and the design's posterior then counts the lot's information.
  std::shared_ptr<const GreyboxPrior> calibration_prior;
  void bind(OptionTable& table);  // keys model.<name>
  std::string validate() const;
  Eigen::RowVectorXd given_network_widths() const;  // network_widths parsed (empty when not given)
};

class Regressor {
 public:
  virtual ~Regressor() = default;
  virtual ModelFamily family() const = 0;
  virtual std::vector<std::string> names() const = 0;
  Eigen::Index size() const { return static_cast<Eigen::Index>(names().size()); }
  // N x size(): the rate error's derivative by each parameter along the inputs (rad/s per unit).
  virtual Eigen::MatrixXd columns(const Signals& inputs) const = 0;
  // Column groups sharing one prior scale (a term, the RBF's nodes), one index per column.
  virtual std::vector<int> groups() const = 0;
  // Indices of the named physical effects (greybox: shupe, hysteresis, thermal_lag): their priors are
  // physical magnitudes (ModelOptions), not the sensor's error scale.
  virtual std::vector<std::pair<std::string, Eigen::Index>> effects() const { return {}; }
  // Groups with a learned prior (the hybrid's network): their prior predictive RMS is what the other groups,
  // fitted to the sensor's error, leave of it - the scale the evidence gives the network on that residual.
  virtual std::vector<int> residual_groups() const { return {}; }
};

// The grey-box scale-factor grid over a domain: temperatures evenly spaced, rates within the domain.
struct SurfaceGrid {
  std::vector<double> temperatures_c, rates_dps;
};
SurfaceGrid greybox_grid(const ModelOptions& options, const Domain& domain);
// The grey-box fit's options (model/greybox_fit.h) for the design's model over a domain (its thermal lag is
// linearised here, fitted there; hysteresis is not a grey-box term).
GreyboxOptions greybox_options(const ModelOptions& options, const Domain& domain);
// The physics terms' scaling (physics_terms.h) of the design's regressors: centred and scaled to the domain.
TermScaling domain_scaling(const Domain& domain);

// The options of `gyrosid calibrate` that fit the model a design assumed (model, solver, options), as YAML.
// The hybrid is given `noise`, the sensor's noise model the design's Fisher information whitened with
// (noise=given), when the hybrid can hold it (white, at most one Gauss-Markov process, rate random walk);
// otherwise it estimates its own (noise=auto), and the YAML says why.
std::string calibration_yaml(ModelFamily family, const ModelOptions& options, const Domain& domain, const NoiseSpec& noise);

// `nominal` is the sensor's error model and `coil_tau_s` its probe-to-coil lag: the expansion point of the
// grey-box thermal-lag column. `network` (hybrid only): the nodes the calibration would fit along one
// trajectory (evidence_network.h) instead of the fixed dictionary.
std::unique_ptr<Regressor> make_regressor(ModelFamily family, const ModelOptions& options, const Domain& domain,
                                          const GyroErrorModel& nominal, double coil_tau_s, const NetworkNodes* network = nullptr);

}  // namespace gyrosid::design

namespace gyrosid {
template <>
struct EnumNames<design::ModelFamily> {
  static constexpr std::string_view kNoun = "design model";
  static constexpr std::array<std::pair<design::ModelFamily, std::string_view>, 4> kTable{
      {{design::ModelFamily::rbf, "rbf"},
       {design::ModelFamily::greybox, "greybox"},
       {design::ModelFamily::classical, "classical"},
       {design::ModelFamily::hybrid, "hybrid"}}};
};
}  // namespace gyrosid
