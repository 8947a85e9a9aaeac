#include "design/envelope.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/progress.h"
#include "core/units.h"
#include "core/config.h"

namespace gyrosid::design {

void EnvelopeOptions::bind(OptionTable& t) {
  t.real("envelope.imu_rate_hz", &imu_rate_hz, 1.0, 10000.0, "IMU rate of generated flights (as gyrosid cof)")
      .real("envelope.long_flight_rate_hz", &long_flight_rate_hz, 1.0, 10000.0, "rate of the sensitivity runs of flights over 10 min")
      .real("envelope.horizon_s", &horizon_s, 1.0, 1e6, "the criterion of fit is taken at min(flight end, horizon)", true)
      .real("envelope.start_temp_c", &cof.start_temp_c, -100.0, 200.0, "air temperature at the start of the flights (thesis: 10 C)")
      .real("envelope.rate_limit_dps", &cof.clip_rate_dps, 0.0, 1e4, "flight rates clipped to this range (thesis: 100)")
      .real("envelope.temperature_margin_c", &temperature_margin_c, 0.0, 100.0, "domain margin beyond the flights' temperatures");
}

std::string EnvelopeOptions::validate() const {
  if (uniform == !flights.empty()) return "the envelope is either flights or a uniform domain";
  if (uniform) return uniform_domain.validate();
  return cof.validate();
}

double steady_error(const GyroErrorModel& errors, double temp_c, double rate_radps) {
  GyroEnvironment env;
  env.temp_c = temp_c;
  env.f_s = Eigen::Vector3d(0.0, 0.0, units::kStandardGravity);
  return errors.forward(rate_radps, env) - rate_radps;
}

SteadyGrid steady_grid(const Domain& d, const GyroErrorModel& truth, int nt, int nw) {
  SteadyGrid g;
  g.inputs.rate.resize(nt * nw), g.inputs.temp_c.resize(nt * nw), g.true_error.resize(nt * nw);
  for (int i = 0; i < nt; ++i) {
    for (int j = 0; j < nw; ++j) {
      const int k = i * nw + j;
      g.inputs.t_s.push_back(1e6 * k);
      g.inputs.temp_c(k) = d.temp_min_c + (d.temp_max_c - d.temp_min_c) * i / (nt - 1);
      g.inputs.rate(k) = d.rate_max_radps * (-1.0 + 2.0 * j / (nw - 1));
      g.true_error(k) = steady_error(truth, g.inputs.temp_c(k), g.inputs.rate(k));
    }
  }
  return g;
}

namespace {

constexpr std::size_t kSurfaceSamplesPerAxis = 1500;

FlightEnvelope flight_envelope(const std::string& name, const EnvelopeOptions& o, const TriadSensor& sensor) {
  FlightEnvelope f;
  f.name = name;
  // Sensitivities need the flight's dynamics, not its IMU rate: long flights are generated coarser.
  if (name.ends_with(".csv")) {
    f.flight = std::make_unique<FlightTrajectory>(load_flight_csv(name));
  } else {
    const bool file = name.ends_with(".yaml") || name.ends_with(".yml") || name.starts_with("builtin:");
    const FlightProfile profile = file ? load_flight_profile(ConfigNode::load(name)) : builtin_flight(name);
    f.flight = std::make_unique<FlightTrajectory>(
        generate_flight(profile, profile.duration_s() > 600.0 ? o.long_flight_rate_hz : o.imu_rate_hz));
  }
  f.evaluator = std::make_unique<nav::CofEvaluator>(*f.flight, sensor, nullptr, o.cof);
  f.horizon_s = std::min(o.horizon_s, f.evaluator->duration_s());
  const Excitation& ex = f.evaluator->excitation();
  const auto n = static_cast<Eigen::Index>(std::min<std::size_t>(ex.size(), static_cast<std::size_t>(std::llround(f.horizon_s / f.flight->dt_s))));
  const std::vector<double>& temp = f.evaluator->model_temperature_c();
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    Signals& s = f.axes[ai];
    s.t_s.assign(ex.t_s.begin(), ex.t_s.begin() + n);
    s.rate = Eigen::Map<const Eigen::VectorXd>(f.evaluator->deterministic_outputs()[ai].data(), n);
    s.temp_c = Eigen::Map<const Eigen::VectorXd>(temp.data(), n);
    f.true_error[ai].resize(n);
    for (Eigen::Index k = 0; k < n; ++k) f.true_error[ai](k) = s.rate(k) - ex.omega_ib_b[static_cast<std::size_t>(k)](a);
  }
  return f;
}

}  // namespace

Eigen::Vector3d FlightEnvelope::position_error(const Regressor& regressor, const Eigen::VectorXd& theta) const {
  const Excitation& ex = evaluator->excitation();
  std::array<std::vector<double>, 3> rates;
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    const Eigen::VectorXd residual = true_error[ai] - regressor.columns(axes[ai]) * theta;
    rates[ai].resize(ex.size());
    for (std::size_t k = 0; k < ex.size(); ++k) {
      rates[ai][k] = ex.omega_ib_b[k](a) + (k < static_cast<std::size_t>(residual.size()) ? residual(static_cast<Eigen::Index>(k)) : 0.0);
    }
  }
  return evaluator->position_error(rates, horizon_s);
}

Envelope load_envelope(const EnvelopeOptions& o, const TriadSensor& sensor) {
  if (auto p = o.validate(); !p.empty()) fail("design envelope: ", p);
  Envelope e;
  if (o.uniform) {
    e.domain = o.uniform_domain;
    SteadyGrid grid = steady_grid(e.domain, sensor.gyros[2].errors);
    e.uniform_samples = std::move(grid.inputs);
    e.uniform_true_error = std::move(grid.true_error);
    return e;
  }
  double t_lo = INFINITY, t_hi = -INFINITY, w_hi = 0.0;
  for (const auto& name : o.flights) {
    e.flights.push_back(flight_envelope(name, o, sensor));
    const FlightEnvelope& f = e.flights.back();
    for (const auto& s : f.axes) t_lo = std::min(t_lo, s.temp_c.minCoeff()), t_hi = std::max(t_hi, s.temp_c.maxCoeff());
    for (const auto& w : f.evaluator->excitation().omega_ib_b) w_hi = std::max(w_hi, w.cwiseAbs().maxCoeff());
  }
  e.domain.temp_min_c = t_lo - o.temperature_margin_c;
  e.domain.temp_max_c = t_hi + o.temperature_margin_c;
  e.domain.rate_max_radps = units::dps_to_radps(std::ceil(units::radps_to_dps(w_hi) - 1e-6));  // whole deg/s
  return e;
}

Linearisation linearise(const Envelope& e, const Regressor& regressor) {
  Linearisation out;
  if (e.uniform_samples) out.uniform_columns = regressor.columns(*e.uniform_samples);
  const Eigen::Index p = regressor.size();
  Progress progress("design: linearising the criterion of fit", e.flights.size());
  std::size_t done = 0;
  for (const auto& f : e.flights) {
    FlightLinearisation lin;
    const Excitation& ex = f.evaluator->excitation();
    std::array<std::vector<double>, 3> reference;
    for (int a = 0; a < 3; ++a) {
      reference[static_cast<std::size_t>(a)].resize(ex.size());
      for (std::size_t k = 0; k < ex.size(); ++k) reference[static_cast<std::size_t>(a)][k] = ex.omega_ib_b[k](a);
    }
    // The position error's gradient by each axis's rate at each step, once for every parameter: a residual of
    // -column j on axis a moves it by -gradient_a column_j.
    const std::array<Eigen::Matrix3Xd, 3> gradient = f.evaluator->position_error_gradient(reference, f.horizon_s);
    lin.sensitivity = Eigen::MatrixXd::Zero(3, p);
    std::vector<Eigen::MatrixXd> surface;
    std::vector<Eigen::VectorXd> surface_error;
    for (int a = 0; a < 3; ++a) {
      const auto ai = static_cast<std::size_t>(a);
      const Eigen::MatrixXd cols = regressor.columns(f.axes[ai]);
      if (cols.rows() > gradient[ai].cols()) fail("design: flight '", f.name, "' has more model inputs than INS steps to its horizon");
      lin.sensitivity -= gradient[ai].leftCols(cols.rows()) * cols;
      const Eigen::Index stride = std::max<Eigen::Index>(1, cols.rows() / static_cast<Eigen::Index>(kSurfaceSamplesPerAxis));
      const Eigen::Index m = (cols.rows() + stride - 1) / stride;
      Eigen::MatrixXd sub(m, p);
      Eigen::VectorXd err(m);
      for (Eigen::Index i = 0; i < m; ++i) sub.row(i) = cols.row(i * stride), err(i) = f.true_error[ai](i * stride);
      surface.push_back(std::move(sub));
      surface_error.push_back(std::move(err));
    }
    Eigen::Index rows = 0;
    for (const auto& s : surface) rows += s.rows();
    lin.surface_columns.resize(rows, p);
    lin.surface_true_error.resize(rows);
    Eigen::Index at = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      lin.surface_columns.middleRows(at, surface[a].rows()) = surface[a];
      lin.surface_true_error.segment(at, surface[a].rows()) = surface_error[a];
      at += surface[a].rows();
    }
    out.flights.push_back(std::move(lin));
    progress.update(++done);
  }
  progress.finish();
  return out;
}

std::vector<std::array<double, 2>> Envelope::temperature_rate_points() const {
  std::vector<std::array<double, 2>> out;
  if (uniform_samples) {
    for (Eigen::Index i = 0; i < uniform_samples->size(); ++i) out.push_back({uniform_samples->temp_c(i), units::radps_to_dps(uniform_samples->rate(i))});
  }
  for (const auto& f : flights) {
    for (const auto& s : f.axes) {
      const Eigen::Index stride = std::max<Eigen::Index>(1, s.size() / 2000);
      for (Eigen::Index i = 0; i < s.size(); i += stride) out.push_back({s.temp_c(i), units::radps_to_dps(s.rate(i))});
    }
  }
  return out;
}

}  // namespace gyrosid::design
