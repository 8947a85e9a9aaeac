// What a calibration trajectory shows a model: the model's inputs (noise-free measured rate, probe
// temperature) at a set of observation times, the sensor's deterministic rate error there (the target a
// noise-free calibration would fit), and the time each observation stands for.
//
// The times are either a trajectory's own samples (weight = its sample interval) or a quadrature of the
// programme (weight = the span it stands for): for white noise of density N the Fisher information of a
// linear model, sum_k a_k a_k' dt_k / N^2, is the same integral either way, so optimisers work on a few
// points per rate cycle and evaluations on the real samples.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "model/physics_terms.h"
#include "sensor/gyro_sensor.h"
#include "trajectory/table_profile.h"

namespace gyrosid::design {

struct Observations {
  Signals inputs;              // t_s, rate = noise-free measured rate (rad/s), temp_c = probe (deg C)
  Eigen::VectorXd true_error;  // measured - true input rate, rad/s
  Eigen::VectorXd weight_s;    // seconds each observation stands for
  Eigen::Index size() const { return inputs.size(); }
};

// A relaxed rate programme: at every observation time the table rate is replaced by `rate_nodes` (a
// quadrature of the rate occupancy of a triangle cycle), each taking `weights` of the observation's span.
struct RateRelaxation {
  std::vector<std::vector<double>> rate_nodes_radps;  // per observation time
  std::vector<double> weights;                        // per node, summing to 1
};

// The gyro (input axis body z) along `profile` at `times` with the sensor's thermal path. With
// `relaxation`, each time yields one observation per rate node, in time order.
Observations observe(const TableProfile& profile, const std::vector<double>& times, const std::vector<double>& weights_s,
                     const GyroSensor& gyro, const ThermalPath& thermal, const RateRelaxation* relaxation = nullptr);

// Quadrature of a programme: one point in each of equal sub-intervals of every segment, at most
// `max_spacing_s` long and at least `points_per_cycle` per rate cycle; weights are the sub-interval lengths.
// The point sits at the golden-ratio sequence's fraction of its sub-interval, not its midpoint: with a whole
// number of points per cycle, midpoints hit the same phases - the same few rates - in every cycle (the
// aliasing the thesis fixed by sampling its scans at 1111 instead of 1000 points, s5.2), and the
// information of the rates between them would be lost.
struct Quadrature {
  std::vector<double> times, weights_s;
};
Quadrature programme_quadrature(const TableProfile& profile, double max_spacing_s, int points_per_cycle);
// A trajectory's own samples with their intervals as weights.
Quadrature sample_quadrature(const std::vector<double>& sample_times, double duration_s);

}  // namespace gyrosid::design
