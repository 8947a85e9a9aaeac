// A production lot: the population of grey-box units of one gyro type, learned from N calibrated units
// (empirical Bayes), as the prior a new unit is calibrated with and the family it is screened against.
//
// Physics: each unit u is a point theta_u in the grey-box coordinates (model/greybox_prior.h: bias values,
// the scale-factor surface's nodes, Shupe, ...). The population is a Gaussian N(mu, Sigma) with a low-rank
// covariance - probabilistic PCA (Tipping & Bishop 1999) of the standardised coordinates
//   z = S^-1 (theta - mu),  S = diag(sd),   Sigma_z = W W' + psi I,
// W the k leading principal directions of the units' z scaled by sqrt(lambda_i - psi), psi the mean
// variance left outside them: the modes a production process varies in (a surface's magnitude, a bias
// law's tilt) and an isotropic rest. k is the fewest modes holding `variance_kept` of the variance.
// With the units' estimation sd known (the fit's diagonal), S is that sd, so the estimation noise has variance
// about 1 in z, and the modes are kept where they clear the Marchenko-Pastur edge of N units' noise; that noise
// is then subtracted - Sigma_z = W W' + psi I has variance lambda_i - 1 along mode i and, elsewhere, the rest's
// mean variance less 1, floored at a tenth of that mean - so Sigma is the population's own spread, not the
// units' scatter about it (lot_model.cpp fit_population). Without it, S is the units' sd; nothing is subtracted.
// All of it from the units' moments (UnitMoments: N, mean, p x p scatter), read one unit at a time, so a lot of
// any size is learned in the memory of its model; a leave-one-out population is the moments less one unit's.
// Noise: the log of each unit's white noise (noise/identify.h on the fit's residual), normal across units.
// Screening: the leave-one-out Mahalanobis distances d_u^2 = r' (Sigma_-u + C_u)^-1 r of the training units
// (C_u the diagonal of a unit's estimation covariance), over every coordinate and, marginally, over each
// group of them (bias, surface, shupe, ...), each matched by moments to a scaled chi-square a chi^2_nu - the
// calibrated nulls of lot/screen.h. (A defect in one term, a doubled Shupe coefficient, moves one coordinate
// of 77: the omnibus distance dilutes it, the term's own test does not.)
// Conditional tests, for a term of one coordinate (Shupe, asymmetry): a short recording barely separates Shupe from
// the bias law, so the unit's own estimate of it is loose and its marginal test weak; refitted with the lot's
// prior on every other coordinate and none on the term's (model/greybox_fit.h's MAP, the term's prior variance
// inflated 10^6-fold), its estimate is as sharp as the recording allows given the lot (lot_unit.h conditional_z):
//   z = (theta_g - mu_g) / sqrt(v_g + Sigma_gg),   v_g the refit's variance of theta_g,
// and d^2 = z^2 is referred to a scaled chi-square matched by moments to the null's units' z^2 - each unit's own
// recording refitted with the lot learned without it (lot_without): a unit inside its lot scores about 0.7 of
// the z^2 of one outside (family A of experiments/production_lot, 50 units), and a heavy-tailed term (a
// log-normal Shupe coefficient) gets a heavier-tailed null than chi^2_1.
// Robustness: units whose leave-one-out p-value is below trim_alpha are left out and the lot learned again
// (once): a defective unit in the training sample must not widen the family. In a lot of more than max_loo_units,
// the units beyond the null's sample are tested too (lot_model.cpp TrimScreen).
#pragma once

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "model/greybox_prior.h"
#include "solvers/common/options.h"

namespace gyrosid {

// A distance's null, d^2 ~ scale chi^2_dof, matched by moments to the leave-one-out distances.
struct DistanceNull {
  double scale = 1.0, dof = 1.0;
  double p_value(double d2) const;
  // The scaled chi-square with the mean and variance of the distances d2 (mean > 0).
  static DistanceNull matched_to(const std::vector<double>& d2);
};

// One calibrated unit, as the lot sees it.
struct LotUnit {
  std::string name;
  Eigen::VectorXd theta;             // greybox coordinates
  Eigen::VectorXd theta_variance;    // its estimate's variances; empty when unknown (a model file). The diagonal
                                     // only: a unit's spooled row stays 2 p numbers, and the null and the
                                     // screening use the same form
  double white_dph_at_1hz = 0.0;     // 0 when unknown
  double recording_min = 0.0;        // the recording's length; 0 when unknown
  Eigen::VectorXd conditional_z;     // against the lot it is screened with (lot_unit.h); empty when not scored
  Eigen::VectorXd misfit;            // its fit's mean residual by rate (MisfitPopulation); empty when unknown
};

// What the units' calibrations leave unexplained, by rate: each unit's mean residual in bins of the rate (the
// surface grid's intervals cut in four), in standard errors of its own residual (m_b = mean_b / (s / sqrt(n_b)),
// s the residual's sd: a noisier unit is not out of family by its misfit), so that a shape the grey-box
// structure cannot hold - a ripple between the grid's nodes, a dead band - is seen where the coordinates are
// blind to it. The lot keeps each bin's mean and sd across its units (a misfit the whole type shares is in the
// mean); a unit's misfit distance is
//   d^2 = sum_b ((m_b - mean_b) / sd_b)^2   over the bins both have,
// referred to a scaled chi-square matched to the lot's units' leave-one-out distances (lot/misfit.cpp).
struct MisfitPopulation {
  std::vector<double> rate_edges_dps;  // bin b is [edges[b], edges[b + 1]); empty: no test
  Eigen::VectorXd mean, sd;            // of m_b per bin; NaN where fewer than 3 units had the bin
  DistanceNull null;
  bool learned() const { return mean.size() > 0; }
  // d^2 of a unit's misfit, and the bin of largest contribution (-1: no bin in common).
  double distance2(const Eigen::VectorXd& misfit, Eigen::Index* largest = nullptr) const;
  nlohmann::json to_json() const;
};

// The misfit bins of a structure: its surface rate grid's intervals, each cut in four (none without the surface).
std::vector<double> misfit_rate_edges_dps(const GreyboxOptions& structure);
// A fit's mean residual in each bin of the rate (deg/s), in standard errors (above); NaN where a bin has fewer than
// 10 samples.
Eigen::VectorXd misfit_by_rate(const Eigen::VectorXd& residual_dph, const Eigen::VectorXd& rate_dps, const std::vector<double>& edges_dps);
class LotUnits;
// The misfit population of units[keep], its null from the leave-one-out distances of units[loo] (each against
// the others of keep); not learned (learned() false) when some unit has no misfit or fewer than 5 units do.
MisfitPopulation learn_misfit(const LotUnits& units, const std::vector<std::size_t>& keep, const std::vector<std::size_t>& loo,
                              std::vector<double> edges_dps);
MisfitPopulation misfit_from_json(const nlohmann::json& j, const std::string& source);

// The units a lot is learned from, read one at a time: in memory (LotUnitsInMemory), or spooled on disk for a
// large lot (lot_unit.h CalibratedUnits), so that learning holds the population's moments, not the units.
class LotUnits {
 public:
  virtual ~LotUnits() = default;
  virtual std::size_t size() const = 0;
  virtual LotUnit at(std::size_t i) const = 0;
};

class LotUnitsInMemory final : public LotUnits {
 public:
  explicit LotUnitsInMemory(std::vector<LotUnit> units) : units_(std::move(units)) {}
  std::size_t size() const override { return units_.size(); }
  LotUnit at(std::size_t i) const override { return units_.at(i); }

 private:
  std::vector<LotUnit> units_;
};

// What the population of a set of units rests on: their count, mean, scatter about the mean
// sum (theta - mean)(theta - mean)' and summed estimation variances - p^2 numbers, whatever the number of units.
// add is Welford's update (units added in index order give the same bits on every layout); remove is its exact
// inverse, a leave-one-out in O(p^2).
struct UnitMoments {
  double count = 0.0, variance_count = 0.0;
  Eigen::VectorXd mean, variance_sum;
  Eigen::MatrixXd scatter;

  explicit UnitMoments(Eigen::Index p);
  void add(const LotUnit& unit);
  void remove(const LotUnit& unit);
  Eigen::VectorXd estimation_sd() const;  // the units' mean estimation sd; empty when some unit's is unknown
};

struct LotOptions {
  double variance_kept = 0.99;  // of the standardised variance, by the modes
  int max_modes = 12;
  double trim_alpha = 1e-4;     // leave-one-out p-value below which a training unit is left out
  int max_loo_units = 200;      // the null's leave-one-out distances from at most this many units (evenly spaced)
  OptionTable table();
  std::string validate() const;
};

struct LotModel {
  OptionMap greybox_options;  // the units' structure, as `calibrate --set` keys
  GreyboxOptions structure;
  std::vector<GreyboxCoordinate> coordinates;
  std::vector<std::string> unit_names, left_out;  // learned from / left out as out of family
  Eigen::VectorXd mean, scale;                    // mu, diag(S)
  Eigen::MatrixXd modes;                          // W: p x k, standardised
  Eigen::VectorXd mode_variance;                  // lambda_1..k (standardised)
  double residual_variance = 0.0;                 // psi
  double log_noise_mean = 0.0, log_noise_sd = 0.0;  // of ln(white dph at 1 Hz); sd 0: no noise known
  int noise_units = 0;
  double recording_min = 0.0;                     // median length of the recordings the null is calibrated on (0: unknown)
  std::vector<std::string> tests;                 // "all", then each coordinate group
  std::vector<DistanceNull> nulls;                // one per test
  std::vector<double> loo_distance;               // d_u^2 over every coordinate, of the null
  std::vector<std::size_t> kept_units, null_units;  // learned from / the null rests on (indices into learn_lot's units); not saved
  std::shared_ptr<const UnitMoments> moments;     // of the kept units (lot_without); not saved
  std::vector<std::string> conditional_terms;     // terms with a conditional test (set_conditional_nulls), and
  std::vector<DistanceNull> conditional_nulls;    // their nulls of z^2
  MisfitPopulation misfit;                        // of the null's recordings; not learned from model files
  std::string source;                             // the file it was read from

  Eigen::MatrixXd covariance() const;             // Sigma = S (W W' + psi I) S
  GreyboxPrior prior() const;
  nlohmann::json to_json() const;                 // the "population" of a gyrosid-prior/1 file
  nlohmann::json tests_json() const;
  static LotModel from_json(const nlohmann::json& population, const std::string& source);
};

// r' (Sigma + diag(v))^-1 r (v empty: none) for each of `tests` ("all": every coordinate; a group: its
// coordinates' marginal), the screening's distances.
std::vector<double> lot_distances(const Eigen::VectorXd& r, const Eigen::MatrixXd& sigma, const Eigen::VectorXd& v,
                                  const std::vector<GreyboxCoordinate>& coordinates, const std::vector<std::string>& tests);

// `screen_units` (optional, one per unit, same order): the same units on the programme a production line
// screens with; the null is then their leave-one-out distances from the others' population (learned from
// `units`), so the screening's false-alarm rate holds for that programme.
LotModel learn_lot(const LotUnits& units, const OptionMap& greybox_options, const LotOptions& options = {},
                   const LotUnits* screen_units = nullptr);
inline LotModel learn_lot(const std::vector<LotUnit>& units, const OptionMap& greybox_options, const LotOptions& options = {}) {
  return learn_lot(LotUnitsInMemory(units), greybox_options, options);
}

// The terms of one coordinate a conditional test can be made for (not the lag, whose prior the lag search takes).
std::vector<std::string> single_coordinate_terms(const std::vector<GreyboxCoordinate>& coordinates);
// The lot learned from the same units without units[u] (u among lot.kept_units): its population refitted from the
// lot's moments less the unit's, the rest the same.
LotModel lot_without(const LotModel& lot, const LotUnits& units, std::size_t u, const LotOptions& options = {});
// z[u]: the conditional scores (lot_unit.h conditional_z) of the null's units, one per single-coordinate term.
void set_conditional_nulls(LotModel& lot, const std::vector<Eigen::VectorXd>& z);

// The lot when the file is one - JSON with a `population` - read in one parse; none for a prior over sensors
// without one (members only) or a YAML file.
std::optional<LotModel> load_lot_if_learned(const std::string& path);
// The lot in a gyrosid-prior/1 file (`population`); Error naming the file when it has none.
LotModel load_lot(const std::string& path);

}  // namespace gyrosid
