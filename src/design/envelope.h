// The application envelope: where the calibrated gyro will fly. Either flights (the built-in short, medium
// and long of the thesis, a flight YAML or CSV) scored by the criterion of fit (nav/criterion_of_fit.h), or
// a uniform operating domain in (T, w).
//
// For each flight the criterion is linearised in the model's parameters: with the compensation residual
// r_a(t) = e_a(t) - A_a(t) theta on gyro axis a, the INS position error at the horizon (the flight's end,
// at most one hour - the long flight's "error after 1 h") is
//   dp = m + S (theta - theta_bar),   S = d dp / d theta,  m = dp(e - A theta_bar)
// with theta_bar the expected estimate (its value on noise-free data)
// S (3 x p) comes from the strapdown INS itself: S = -sum_a G_a A_a, with G_a (3 x N) the gradient of the
// position error by axis a's rate at every step about the reference path, from one backward (adjoint) pass
// of the INS per flight (nav/strapdown_adjoint.h) for all parameters at once; m is one exact run with the
// expected model's residual.
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "design/regressor.h"
#include "model/physics_terms.h"
#include "nav/criterion_of_fit.h"
#include "sensor/gyro_sensor.h"
#include "solvers/common/options.h"

namespace gyrosid::design {

struct EnvelopeOptions {
  std::vector<std::string> flights{"short", "medium", "long"};  // empty with uniform
  bool uniform = false;
  Domain uniform_domain;               // the operating domain of `uniform`
  double imu_rate_hz = 100.0;          // flights generated at this rate (as gyrosid cof)
  double long_flight_rate_hz = 10.0;   // sensitivities of flights longer than 10 min are computed at this rate
  double horizon_s = 3600.0;           // the criterion is taken at min(flight end, horizon)
  nav::CofOptions cof;                 // start temperature, probe, rate clipping - as gyrosid cof
  double temperature_margin_c = 5.0;   // domain margin beyond the flights' temperatures
  void bind(OptionTable& table);       // keys envelope.<name>
  std::string validate() const;
};

struct FlightEnvelope {
  std::string name;
  double horizon_s = 0.0;
  std::unique_ptr<FlightTrajectory> flight;   // owned: the evaluator refers to it
  std::unique_ptr<nav::CofEvaluator> evaluator;
  std::array<Signals, 3> axes;                // model inputs per gyro axis up to the horizon
  std::array<Eigen::VectorXd, 3> true_error;  // what the compensation must remove, rad/s

  // m: the position error (NED, m) the residual of the parameters `theta` leaves at the horizon.
  Eigen::Vector3d position_error(const Regressor& regressor, const Eigen::VectorXd& theta) const;
};

struct Envelope {
  std::vector<FlightEnvelope> flights;
  std::optional<Signals> uniform_samples;   // the uniform domain on a grid, steady temperature
  Eigen::VectorXd uniform_true_error;
  Domain domain;                             // the (T, w) region the envelope spans (with its margin)

  // Every sample of the envelope as (T deg C, w deg/s), decimated, for plots.
  std::vector<std::array<double, 2>> temperature_rate_points() const;
};

Envelope load_envelope(const EnvelopeOptions& options, const TriadSensor& sensor);

// The envelope seen through one model: per flight the sensitivity S and the model's columns and the true
// error over a decimation of its samples (surface statistics); the columns on the uniform grid.
struct FlightLinearisation {
  Eigen::MatrixXd sensitivity;        // S, 3 x p, m per unit of theta
  Eigen::MatrixXd surface_columns;
  Eigen::VectorXd surface_true_error;
};
struct Linearisation {
  std::vector<FlightLinearisation> flights;
  Eigen::MatrixXd uniform_columns;
};
Linearisation linearise(const Envelope& envelope, const Regressor& regressor);

// The sensor's deterministic rate error at steady temperature on a level table, input axis up (thesis fig 3.12).
double steady_error(const GyroErrorModel& errors, double temp_c, double rate_radps);
// A grid over the domain at steady temperature (samples 10^6 s apart, so temperature rates vanish) and the
// sensor's error there.
struct SteadyGrid {
  Signals inputs;
  Eigen::VectorXd true_error;
};
SteadyGrid steady_grid(const Domain& domain, const GyroErrorModel& truth, int temperatures = 21, int rates = 41);

}  // namespace gyrosid::design
