// Screening a unit against its lot (lot_model.h): does it belong to the family the lot was learned from?
//
// Physics: the Mahalanobis distance of the unit's coordinates from the lot,
//   d^2 = r' (Sigma + C)^-1 r,   r = theta - mu,  C the diagonal of the unit's estimation covariance (as in the null),
// referred to the lot's calibrated null a chi^2_nu (the training units' leave-one-out distances, matched by
// moments), and the same over each coordinate group alone (its marginal): p_physics is the Bonferroni
// min(1, K min_k p_k) over the K tests, so a defect in one term is not diluted by the other 76 coordinates;
// the conditional tests of a one-coordinate term given the rest, and the misfit by rate (lot_model.h
// MisfitPopulation: a shape the structure cannot hold, named by its rate bin), when given, are among the K.
// Noise: z = (ln N - m) / (s sqrt(1 + 1/n)) of the unit's white noise against the lot's log-normal, two-sided p_noise from Student's t with n - 1 degrees of freedom (n units). The unit's p-value is the Bonferroni
// min(1, 2 min(p_physics, p_noise)), so the false-alarm rate is at most alpha.
// The null is calibrated on the lot's own recordings: a unit recorded on a programme of another length (more
// than 20 % apart) is screened with a warning - its estimate's errors, and so its distances, are of another kind.
// Reasons name what is out of family: d^2 splits exactly into the contributions r_j [(Sigma + C)^-1 r]_j,
// summed over a coordinate group (bias, Shupe, ...) or, for the scale-factor surface, over a region (a grid
// temperature and the sign of the rate); negative sums (a region pulling against another) count as zero in the
// shares. A group whose own test fails is named first (the surface by its region of largest share); else the
// regions holding at least a fifth of d^2, at least the largest; and the noise when its own test fails.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "lot/lot_model.h"

namespace gyrosid {

struct ScreenOptions {
  double alpha = 0.01;  // false-alarm rate
  std::string validate() const;
};

struct ScreenResult {
  bool out_of_family = false;
  double p_value = 1.0, p_physics = 1.0, p_noise = 1.0;
  double distance2 = 0.0;  // d^2
  std::vector<std::string> reasons;
  std::string warning;  // why the false-alarm rate may not hold (a recording unlike the lot's)
  nlohmann::json contributions;  // share of d^2 per group or surface region
  nlohmann::json tests = nlohmann::json::object();  // per test ("all", each group): distance2, p_value
  nlohmann::json to_json() const;
};

// The unit's conditional scores (unit.conditional_z), when it has them, are tested where the lot has their nulls.
ScreenResult screen_unit(const LotModel& lot, const LotUnit& unit, const ScreenOptions& options = {});

}  // namespace gyrosid
