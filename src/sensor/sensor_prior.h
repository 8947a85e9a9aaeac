// A prior over sensors (format gyrosid-prior/1): what is known of a gyro before it is calibrated - its type, a
// datasheet, earlier units - as a finite weighted set of sensor configs, the members. A design for a prior
// (`gyrosid design --prior`) minimises the weighted mean of its objective over the members and reports its
// prediction on each; a production lot learned from units is written in the same format.
//
//   format: gyrosid-prior/1
//   name: open-loop FOG, type A
//   members:                         # sensor configs (paths relative to this file, or builtin:...)
//     - {sensor: builtin:sensors/open_loop_fog.yaml, weight: 1}
//     - sensor: fog_with_drift.yaml
//       weight: 1
//       draws:                       # optional: `count` more members drawn around this one
//         count: 4
//         seed: 1
//         vary:                      # a dotted path of the sensor config (list items by index) -> its law
//           bias.constant_dph: {sd: 2}                       # + N(0, sd^2)
//           scale_factor.surface.error_ppm: {log_sd: 0.3}    # x exp(N(0, log_sd^2))
//           noise.gauss_markov.0.tau_s: {log_sd: 0.5}
//
// A path names a number or a (nested) list of numbers; one draw per path and member moves all of them
// together (a surface scaled as a whole, the unit-to-unit variation of a mode, not an independent draw per
// grid point). Draws are named "<member name> (draw j)", take their parent's weight and come from the
// RandomStream "prior/<parent index>/<j>/<path>" and follow their parent: the same file and seed give the same
// members.
// A member's `sensor` may also be the config itself, inline (a map; no draws): `gyrosid lot learn` writes a
// lot's members so, beside its `population` (lot/lot_model.h), which a grey-box design counts as the prior its
// calibration fits with (design/regressor.h, ModelOptions::calibration_prior).
// A file with `kind` (gyro or triad) instead of `format` is a sensor config: the prior of that one sensor.
#pragma once

#include <string>
#include <vector>

#include "sensor/sensor_config.h"

namespace gyrosid {

// The format of a prior over sensors, a learned lot included (lot/lot_members.h writes one).
inline constexpr const char* kSensorPriorFormat = "gyrosid-prior/1";

struct SensorPriorMember {
  std::string name;    // the sensor's name (draws: "<parent> (draw j)")
  std::string origin;  // where it comes from: the config path, and the draw
  SensorSpec sensor;
  double weight = 1.0;  // relative: the members' weights need not sum to 1
};

struct SensorPrior {
  std::string name;
  std::string source;  // the file it was read from
  std::vector<SensorPriorMember> members;  // the first is the nominal sensor (the envelope's flights, the plots)
  double total_weight() const;
};

// Errors name the file, the line and the key (a missing path in `vary` also names the member's sensor config).
SensorPrior load_sensor_prior(const std::string& path);

}  // namespace gyrosid
