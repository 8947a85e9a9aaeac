// The optimisation problem a design solver sees: the design space (design_space.h) and the objective of
// the design context (assessment.h) evaluated on a quadrature of each candidate programme - exactly on the
// programme for the box encoding, on the rate-occupancy relaxation for the smooth one. Under a prior over
// sensors (sensor/sensor_prior.h) the objective is the weighted mean over its members' contexts,
//   J(programme) = sum_k w_k J_k(programme) / sum_k w_k,
// each member seeing the programme through its own thermal path and judged against its own error and noise:
// the expected objective over the prior (Bayesian design, Chaloner & Verdinelli 1995, s2.2; the criteria are
// logs, so this is the expected log criterion: a design good on every member, not on the average member).
// With prior.worst_share = s < 1 it is the mean over the worst members holding the share s of the weight
// (the upper-tail mean, conditional value at risk at level 1 - s; Rockafellar & Uryasev 2000): the design
// for the sensors it does worst on. The boundary member counts with the part of its weight that fills s, so
// the statistic is continuous in the members' objectives.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "design/assessment.h"
#include "design/design_space.h"

namespace gyrosid::design {

struct PriorOptions {
  double worst_share = 1.0;       // the share of the prior's weight whose mean objective is minimised (1: all)
  void bind(OptionTable& table);  // keys prior.<name>
};

// The mean of `values` over the largest ones holding `share` of the total weight (above).
double upper_tail_mean(const std::vector<double>& values, const std::vector<double>& weights, double share);

struct QuadratureOptions {
  double max_spacing_s = 10.0;   // exact programme: at most this far apart ...
  int points_per_cycle = 12;     // ... and this many per rate cycle
  int relaxed_times = 24;        // smooth relaxation: time nodes per segment ...
  int relaxed_rates = 5;         // ... times Gauss-Legendre rate nodes
  void bind(OptionTable& table); // keys quadrature.<name>
};

// A member of a prior over sensors: its design context (same envelope, model and criterion as the others)
// and its weight (> 0).
struct WeightedContext {
  const DesignContext* context = nullptr;
  double weight = 1.0;
};

class DesignProblem {
 public:
  DesignProblem(const DesignContext& context, const DesignSpace& space, QuadratureOptions quadrature);
  // `members` non-empty; the first is the nominal one (context()).
  DesignProblem(std::vector<WeightedContext> members, const DesignSpace& space, QuadratureOptions quadrature, PriorOptions prior = {});

  const DesignContext& context() const { return *members_.front().context; }
  const std::vector<WeightedContext>& members() const { return members_; }
  const DesignSpace& space() const { return space_; }

  // An adaptive session's recorded segments (gyrosid session): every programme is judged as their continuation,
  // the objective that of everything the final calibration will see (the information adds; the thermal path
  // runs on from where the recorded part left the coil). Box encoding only: the smooth relaxation refuses it.
  void set_recorded(TableProfile recorded) { recorded_ = std::move(recorded); }
  const TableProfile& recorded() const { return recorded_; }
  // The programme after the recorded segments (itself when none are).
  TableProfile continued(const TableProfile& programme) const { return concatenate(recorded_, programme); }

  // cof_minimax: offsets added to the flights' log ratios (DesignContext::objective; exact_selection.h).
  void set_flight_offsets(std::vector<double> offsets) { offsets_ = std::move(offsets); }
  const std::vector<double>& flight_offsets() const { return offsets_; }

  double objective(const TableProfile& programme) const;      // on the programme's quadrature
  double box_objective(const Eigen::VectorXd& v) const { return objective(space_.decode_box(v)); }
  double smooth_objective(const SmoothProgramme& x) const;    // on the relaxation
  Observations observe_programme(const TableProfile& programme) const;  // as the nominal member sees it

 private:
  // The weighted mean over the members of their objectives on the observations `observe(member)` gives.
  template <class Observe>
  double mean_objective(const Observe& observe) const;

  std::vector<WeightedContext> members_;
  const DesignSpace& space_;
  QuadratureOptions q_;
  PriorOptions prior_;
  std::vector<double> offsets_;
  TableProfile recorded_;
};

}  // namespace gyrosid::design
