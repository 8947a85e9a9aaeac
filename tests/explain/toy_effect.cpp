// A toy effect added from the test binary alone, proving the extension point of explain/effect.h: an effect
// is one class - its physics in a sentence, the candidate it proposes on a recording, its physical
// parameters with units - and one registration line; the property suite of test_effect_properties.cpp then
// runs over it like over the library's own effects (testable, finite columns, planted parameters recovered,
// JSON round trip, separating experiments). It lives in its own test binary (test_effects): every explain
// run of a program tries every registered effect, and the explain tests must see the library's alone.
//
// supply_sensitivity: the bias follows the supply voltage, b = k (V - V_0), one column: the recorded
// supply_v channel (an existing term kind, model/terms/term_kinds.h's channel term).
#include <algorithm>

#include "explain/effect.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {
namespace {

class SupplySensitivity : public Effect {
 public:
  static constexpr const char* kChannel = "supply_v";
  std::string_view id() const override { return "supply_sensitivity"; }
  std::string_view description() const override {
    return "The bias follows the supply voltage: the source's power and the detector's gain move with it.";
  }
  std::string_view parameters_help() const override { return "k_dph_per_v: bias per volt of the supply (deg/h/V)"; }
  Proposal propose(const CandidateContext& c) const override {
    Proposal p;
    if (std::find(c.in.aux.begin(), c.in.aux.end(), kChannel) == c.in.aux.end()) {
      p.untestable = "no supply_v channel in the recording";
    } else if (!c.new_varying_channels({kChannel}, 0.0).empty()) {
      p.candidates.push_back(candidate(channel_term({kChannel})));
    }
    return p;
  }
  std::vector<PhysicalParameter> parameters(const Term&, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    return {PhysicalParameter::estimate("k_dph_per_v", beta(0), sigma(0))};
  }
};

// The one registration line, run before gtest lists or instantiates the tests.
const bool supply_sensitivity_registered = [] {
  extend_effect_registry().add({"supply_sensitivity", "toy: the bias follows the supply voltage", [] { return std::string("k_dph_per_v"); },
                                [] { return std::unique_ptr<Effect>(std::make_unique<SupplySensitivity>()); }});
  return true;
}();

}  // namespace
}  // namespace gyrosid::explain
