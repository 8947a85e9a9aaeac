// The effect library: every effect the finder can name (or localise), in the order candidates are tried.
#include "explain/effects/effects.h"

namespace gyrosid::explain {

const EffectRegistry& effect_registry() { return extend_effect_registry(); }

EffectRegistry& extend_effect_registry() {
  static EffectRegistry registry = [] {
    EffectRegistry r("effect");
    using Factory = std::unique_ptr<Effect> (*)();
    for (Factory make : {effects::temperature_bias, effects::scale_factor_nonlinearity, effects::scale_factor_temperature,
                         effects::scale_factor_asymmetry, effects::shupe, effects::thermal_lag, effects::thermal_hysteresis,
                         effects::warmup_transient, effects::aging_trend, effects::g_sensitivity, effects::g2_sensitivity,
                         effects::magnetic_sensitivity, effects::auxiliary_channel, effects::cross_axis_coupling, effects::bias_step,
                         effects::bias_ramp}) {
      const std::unique_ptr<Effect> e = make();
      const std::string params(e->parameters_help());
      r.add({std::string(e->id()), std::string(e->description()), [params] { return params; },
             [make] { return make(); }});
    }
    return r;
  }();
  return registry;
}

}  // namespace gyrosid::explain
