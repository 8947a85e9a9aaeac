// A simulated recording: the sensor's outputs along an excitation, in the recording format
// (docs/recording_format.md). Single gyro: t_s, ref_rate_dps, temp_c, gyro_dps, chamber_temp_c,
// accel_{x,y,z}_mps2. Triad: t_s, ref_rate_{x,y,z}_dps, gyro_{x,y,z}_dps, temp_c, chamber_temp_c,
// accel_{x,y,z}_mps2, position_id. temp_c is the package probe; the coil temperature stays hidden, as in
// a real recording.
#pragma once

#include <cstdint>
#include <string>

#include "core/excitation.h"
#include "core/recording.h"
#include "sensor/sensor_config.h"

namespace gyrosid {

struct SimulationSummary {
  std::size_t samples = 0;
  std::size_t clamped_samples = 0;    // error surface evaluated beyond its grid (clamp policy)
  std::size_t saturated_samples = 0;  // outputs clipped at the range
};

Recording simulate_recording(const SensorSpec& sensor, const Excitation& excitation, std::uint64_t seed,
                             SimulationSummary* summary = nullptr);

}  // namespace gyrosid
