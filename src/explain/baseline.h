// What a simulation already has and may always re-estimate, as physics terms: the thesis's unified model
// (the baseline family) or the structure of a given calibration model.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "model/calibration_model.h"
#include "model/physics_terms.h"

namespace gyrosid::explain {
// automatic: the surface where the BIC prefers it to the polynomial on the training rows (simulation.h).
enum class BaselineForm { automatic, surface, polynomial };
}  // namespace gyrosid::explain

namespace gyrosid {
template <>
struct EnumNames<explain::BaselineForm> {
  static constexpr std::string_view kNoun = "baseline form";
  static constexpr std::array<std::pair<explain::BaselineForm, std::string_view>, 3> kTable{
      {{explain::BaselineForm::automatic, "auto"},
       {explain::BaselineForm::surface, "surface"},
       {explain::BaselineForm::polynomial, "polynomial"}}};
};
}  // namespace gyrosid

namespace gyrosid::explain {

// The thesis's unified model as terms: bias, bias in T to order 3, and the scale factor either as a
// bicubic surface on the thesis's (T, omega) grid narrowed to the data's range (surface) or as a polynomial
// omega dT^i u^j, i, j <= 3 (polynomial; also when the data span too little for a grid). Only the terms the
// data's ranges support: temperature terms need a few degrees, scale-factor terms some rate. `automatic`
// must be resolved first (choose_baseline_form).
std::vector<Term> baseline_family(BaselineForm form, const Signals& s);
// The terms a given model already has (its coefficients may be re-estimated); its thermal lag in *lag_tau_s.
// None for a black-box model (RBF): it stands for a smooth 2-D error function, whose terms are the baseline
// family's.
std::optional<std::vector<Term>> structure_of(const CalibrationModel& model, double* lag_tau_s);

}  // namespace gyrosid::explain
