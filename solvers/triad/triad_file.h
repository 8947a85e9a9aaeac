// A triad fit as a model file (format gyrosid-model/1, kind "triad"), written in this one place:
//
//   misalignment.matrix / .sigma / .inflation   3 x 3, row i = gyro i; diagonal dimensionless scale-factor
//                                               errors, off-diagonal radians; null where not determined
//   bias_dph                                    each gyro's bias at the reference temperature, with sigma
//   bias                                        the polynomials b_i(T) (deg/h) with sigmas (what compensation reads)
//   g_sensitivity_dph_per_mps2 (+ _sigma)       when estimated
//   observable                                  determined entries, the six angle sums of eq 3.72 and the twelve
//                                               physical angles (none observable alone), notes
//   noise_dph, residual_rms_dph, reference      per gyro: residual sigma and rms of the rows (deg/h), how rows
//   noise_density_radps_rt_hz, sample_rate_hz   were formed; white-noise density N and the sampling rate
//   surfaces                                    each gyro's surface model (or null)
//   summary, training                           the solve and its provenance
#pragma once

#include <nlohmann/json.hpp>

#include "solvers/triad/triad_fit.h"

namespace gyrosid {

nlohmann::json triad_fit_json(const TriadFit& fit, const nlohmann::json& training);

}  // namespace gyrosid
