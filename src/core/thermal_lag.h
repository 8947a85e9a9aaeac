// Thermal lag of a sensor package: the coil (or a probe) sees the chamber temperature through a pure delay
// and a cascade of first-order lags (thesis s4.4: "the temperature at the gyro coils will lag the
// environmental temperature", about 5 min). Each stage obeys  dx_k/dt = (x_{k-1} - x_k) / tau_k,
// x_0(t) = u(t - delay).
//
// The chamber temperature of a calibration trajectory is piecewise linear in time, so the response is
// computed exactly (no integration error): on each interval where the input is linear the augmented system
// z = [x; u; du/dt] is advanced by the matrix exponential exp(M h).
#pragma once

#include <vector>

namespace gyrosid {

// A piecewise-linear signal through knots (t_i, v_i); held constant before the first and after the last.
struct PiecewiseLinear {
  std::vector<double> t;
  std::vector<double> v;

  double at(double time) const;
  double slope_after(double time) const;  // right derivative
  void append(double time, double value);  // knots must be appended in non-decreasing time
};

struct ThermalLagOptions {
  double delay_s = 0.0;
  std::vector<double> tau_s;  // stages from input to output; a zero stage passes its input through
};

struct ThermalLagResponse {
  std::vector<std::vector<double>> stage;  // stage[k][i]: output of stage k at query time i
  std::vector<double> output_rate;         // d(last stage)/dt at each query time, per second
};

// Response at ascending `query_times`. Every stage starts in equilibrium with the input's initial value.
ThermalLagResponse thermal_lag_response(const ThermalLagOptions& options, const PiecewiseLinear& input,
                                        const std::vector<double>& query_times);

}  // namespace gyrosid
