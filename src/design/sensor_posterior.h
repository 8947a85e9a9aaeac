// A prior over sensors (sensor/sensor_prior.h) updated by what a unit recorded: the posterior an adaptive session
// (gyrosid session) redesigns its remaining time for.
//
// Each member m explains the recording y (gyro output, every sample so far) by its own noise-free output f_m on
// the programme that was run, at the recorded times, plus its own noise and an unknown constant bias c:
//   y = f_m + c 1 + e,   e ~ N(0, Sigma_m)   (white + rate random walk + Gauss-Markov, bias instability's
//                                             components included; quantization as white Q^2 / (6 dt^2))
// Sigma_m is applied as a Kalman whitener W_m (design/information.h, no N x N matrix); the constant is integrated
// out under a flat prior, so
//   log L_m = -1/2 [ sum_k log s_k + |W r|^2 - (u'W r)^2 / |u|^2 + log |u|^2 ],  r = y - f_m, u = W 1,
// s_k the innovation variances (the constant -n/2 log 2 pi is dropped: it is the same for every member).
//
// A finite prior rarely holds the unit itself, and a likelihood over thousands of samples then puts all the
// weight on the nearest member - a design for one wrong sensor. The posterior is therefore tempered
// (generalised Bayes, w_m ~ p_m L_m^eta; Grunwald & van Ommen 2017 on the misspecified case): eta = 1 unless it
// leaves fewer effective members (sum w)^2 / sum w^2 than `min_effective_members` (at most half the prior's
// own), then the largest eta that keeps them, by bisection.
#pragma once

#include <string>
#include <vector>

#include "sensor/gyro_sensor.h"
#include "trajectory/table_profile.h"

namespace gyrosid::design {

// log L_m above for one gyro on the programme's `t_s` (seconds from its start, ascending, uniformly sampled),
// `gyro_dps` the recorded output there. Error when the member has no noise (its likelihood is then undefined).
double recording_log_likelihood(const GyroSensor& member, const TableProfile& programme, const std::vector<double>& t_s,
                                const std::vector<double>& gyro_dps);

// (sum w)^2 / sum w^2: how many members the weights amount to.
double effective_members(const std::vector<double>& weights);

struct SensorPosterior {
  std::vector<double> log_likelihood;  // per member
  std::vector<double> weights;         // normalised: they sum to 1
  double learning_rate = 1.0;          // eta
  double effective_members = 0.0;
};

// The tempered posterior (above) from the prior's weights (positive, any sum) and the members' log-likelihoods.
SensorPosterior tempered_posterior(const std::vector<double>& prior_weights, const std::vector<double>& log_likelihood,
                                   double min_effective_members);

}  // namespace gyrosid::design
