// The optimisation problem a design solver sees: the design space (design_space.h) and the objective of
// the design context (assessment.h) evaluated on a quadrature of each candidate programme - exactly on the
// programme for the box encoding, on the rate-occupancy relaxation for the smooth one.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "design/assessment.h"
#include "design/design_space.h"

namespace gyrosid::design {

struct QuadratureOptions {
  double max_spacing_s = 10.0;   // exact programme: at most this far apart ...
  int points_per_cycle = 12;     // ... and this many per rate cycle
  int relaxed_times = 24;        // smooth relaxation: time nodes per segment ...
  int relaxed_rates = 5;         // ... times Gauss-Legendre rate nodes
  void bind(OptionTable& table); // keys quadrature.<name>
};

class DesignProblem {
 public:
  DesignProblem(const DesignContext& context, const DesignSpace& space, QuadratureOptions quadrature);

  const DesignContext& context() const { return context_; }
  const DesignSpace& space() const { return space_; }

  // cof_minimax: offsets added to the flights' log ratios (DesignContext::objective; exact_selection.h).
  void set_flight_offsets(std::vector<double> offsets) { offsets_ = std::move(offsets); }
  const std::vector<double>& flight_offsets() const { return offsets_; }

  double objective(const TableProfile& programme) const;      // on the programme's quadrature
  double box_objective(const Eigen::VectorXd& v) const { return objective(space_.decode_box(v)); }
  double smooth_objective(const SmoothProgramme& x) const;    // on the relaxation
  Observations observe_programme(const TableProfile& programme) const;

 private:
  const DesignContext& context_;
  const DesignSpace& space_;
  QuadratureOptions q_;
  std::vector<double> offsets_;
};

}  // namespace gyrosid::design
