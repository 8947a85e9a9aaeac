// The effects of the library (explain/effect.h), one factory each; effect_registry() lists them in the
// order candidates are tried.
#pragma once

#include <memory>

#include "core/units.h"
#include "explain/effect.h"

namespace gyrosid::explain::effects {

// A coefficient fitted on residuals in deg/h per rad/s of input, as rad/s per rad/s (a dimensionless ratio).
inline constexpr double kDphPerRadps = units::dph_to_radps(1.0);

// Temperature (temperature_effects.cpp).
std::unique_ptr<Effect> temperature_bias();
std::unique_ptr<Effect> shupe();
std::unique_ptr<Effect> thermal_lag();
std::unique_ptr<Effect> thermal_hysteresis();
// Time (time_effects.cpp).
std::unique_ptr<Effect> warmup_transient();
std::unique_ptr<Effect> aging_trend();
// Not physics: changes of the bias at a time, reported as unexplained (time_effects.cpp).
std::unique_ptr<Effect> bias_step();
std::unique_ptr<Effect> bias_ramp();
// Scale factor (scale_factor_effects.cpp).
std::unique_ptr<Effect> scale_factor_asymmetry();
std::unique_ptr<Effect> scale_factor_nonlinearity();
std::unique_ptr<Effect> scale_factor_temperature();
// Recorded channels (channel_effects.cpp).
std::unique_ptr<Effect> g_sensitivity();
std::unique_ptr<Effect> g2_sensitivity();
std::unique_ptr<Effect> magnetic_sensitivity();
std::unique_ptr<Effect> cross_axis_coupling();
std::unique_ptr<Effect> auxiliary_channel();

}  // namespace gyrosid::explain::effects
