#include "nav/criterion_of_fit.h"

#include <algorithm>
#include <cmath>

#include "core/earth_model.h"
#include "core/error.h"
#include "core/random.h"
#include "core/units.h"
#include "model/dataset.h"
#include "nav/strapdown_adjoint.h"
#include "sensor/misalignment.h"

namespace gyrosid::nav {

std::string CofOptions::validate() const {
  if (thermal_delay_s < 0) return str_cat("thermal delay ", thermal_delay_s, " s must be >= 0");
  if (scale_rates && !(clip_rate_dps > 0)) return "scaling rates needs a positive rate limit";
  return "";
}

CofEvaluator::CofEvaluator(const FlightTrajectory& flight, const TriadSensor& sensor, const SensorModel* model, const CofOptions& options)
    : flight_(flight), sensor_(sensor), model_(dynamic_cast<const CalibrationModel*>(model)), triad_(dynamic_cast<const TriadModel*>(model)), options_(options) {
  if (auto p = options.validate(); !p.empty()) fail("criterion of fit: ", p);
  if (model && !model_ && !triad_) fail("criterion of fit: a ", model->kind(), " model of ", model->gyros(), " gyros cannot compensate a triad's flight");
  const std::size_t n = flight.steps();
  if (n < 2) fail("criterion of fit: flight '", flight.name, "' has fewer than two steps");
  const double dt = flight.dt_s;
  for (int i = 0; i < 3; ++i) c_s_b_[static_cast<std::size_t>(i)] = body_from_ia(i, sensor.alignment[static_cast<std::size_t>(i)]).transpose();

  // Reference gyro rates (mean over each interval), clipped or scaled to the calibrated range.
  Excitation& ex = excitation_;
  ex.t_s.resize(n);
  ex.omega_ib_b.resize(n);
  ex.f_b.resize(n);
  double peak = 0.0;
  for (std::size_t k = 0; k < n; ++k) peak = std::max(peak, flight.dtheta[k].cwiseAbs().maxCoeff() / dt);
  max_rate_dps_ = units::radps_to_dps(peak);
  const double limit = units::dps_to_radps(options.clip_rate_dps);
  const double scale = (options.scale_rates && peak > limit) ? limit / peak : 1.0;
  for (std::size_t k = 0; k < n; ++k) {
    ex.t_s[k] = flight.t_s[k + 1];
    Eigen::Vector3d w = flight.dtheta[k] / dt * scale;
    if (options.clip_rate_dps > 0 && !options.scale_rates) {
      for (int a = 0; a < 3; ++a) {
        if (std::abs(w(a)) > limit) {
          w(a) = std::copysign(limit, w(a));
          ++clipped_;
        }
      }
    }
    ex.omega_ib_b[k] = w;
    ex.f_b[k] = flight.dv[k] / dt;
  }

  // Reference INS on the (clipped) reference data: every step kept for the error growth.
  StrapdownIns ins(flight.initial(), dt);
  reference_path_.reserve(n + 1);
  reference_path_.push_back(ins.state());
  for (std::size_t k = 0; k < n; ++k) {
    ins.step(ex.omega_ib_b[k] * dt, flight.dv[k]);
    reference_path_.push_back(ins.state());
  }

  // Air temperature from the altitude (truth when available, else the reference INS), and the coil's.
  const double h0 = reference_path_.front().h;
  air_temp_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double h = flight.truth.size() == n + 1 ? flight.truth[k + 1].h : reference_path_[k + 1].h;
    air_temp_[k] = options.start_temp_c - 0.0065 * (h - h0);
  }
  ex.chamber_temp_c = air_temp_;
  ex.coil_temp_c.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double delayed_t = ex.t_s[k] - options.thermal_delay_s;
    if (delayed_t <= ex.t_s.front()) {
      ex.coil_temp_c[k] = options.start_temp_c;
    } else {
      const double pos = (delayed_t - ex.t_s.front()) / dt;
      const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(pos), n - 2);
      const double frac = pos - static_cast<double>(i);
      ex.coil_temp_c[k] = air_temp_[i] + frac * (air_temp_[i + 1] - air_temp_[i]);
    }
  }
  ex.coil_temp_rate_c_per_s = time_derivative(ex.t_s, ex.coil_temp_c);
  ex.probe_temp_c = options.probe == TemperatureProbe::coil ? ex.coil_temp_c : air_temp_;
  probe_temp_ = ex.probe_temp_c;
  probe_rate_ = time_derivative(ex.t_s, probe_temp_);

  // Noise-free sensor outputs, reused by every run.
  TriadSensor quiet = sensor_;
  for (auto& g : quiet.gyros) g.noise = NoiseOptions{};
  const TriadOutput out = simulate_triad(quiet, ex, 0);
  for (int i = 0; i < 3; ++i) deterministic_[static_cast<std::size_t>(i)] = out.gyro[static_cast<std::size_t>(i)].rate_radps;
}

std::array<std::vector<double>, 3> CofEvaluator::compensate(const std::array<std::vector<double>, 3>& measured) const {
  const std::size_t n = excitation_.size();
  std::array<std::vector<double>, 3> out;
  if (triad_) {  // the three gyros together: what the triad model's probe (the coil) reads, body specific force
    TriadData d;
    d.t_s = excitation_.t_s;
    d.gyro.resize(static_cast<Eigen::Index>(n), 3);
    d.temp_c.resize(static_cast<Eigen::Index>(n), 3);
    d.accel.resize(static_cast<Eigen::Index>(n), 3);
    for (std::size_t k = 0; k < n; ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      for (int a = 0; a < 3; ++a) d.gyro(row, a) = measured[static_cast<std::size_t>(a)][k];
      d.temp_c.row(row).setConstant(probe_temp_[k]);
      d.accel.row(row) = excitation_.f_b[k].transpose();
    }
    const Eigen::MatrixX3d c = triad_->compensate(d);
    for (int a = 0; a < 3; ++a) out[static_cast<std::size_t>(a)].assign(c.col(a).data(), c.col(a).data() + c.rows());
    return out;
  }
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    Dataset d;
    d.features = model_->features();
    d.t_s = excitation_.t_s;
    d.x.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(d.features.size()));
    d.measured = Eigen::Map<const Eigen::VectorXd>(measured[ai].data(), static_cast<Eigen::Index>(n));
    d.reference = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(n), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t f = 0; f < d.features.size(); ++f) {
      const std::string& name = d.features[f];
      const auto col = static_cast<Eigen::Index>(f);
      for (std::size_t k = 0; k < n; ++k) {
        const auto row = static_cast<Eigen::Index>(k);
        if (name == "measured_rate") d.x(row, col) = measured[ai][k];
        else if (name == "temperature") d.x(row, col) = probe_temp_[k];
        else if (name == "temperature_rate") d.x(row, col) = probe_rate_[k];
        else if (name == "accel_x_mps2") d.x(row, col) = (c_s_b_[ai] * excitation_.f_b[k])(0);
        else if (name == "accel_y_mps2") d.x(row, col) = (c_s_b_[ai] * excitation_.f_b[k])(1);
        else if (name == "accel_z_mps2") d.x(row, col) = (c_s_b_[ai] * excitation_.f_b[k])(2);
        else fail("criterion of fit: the model's input '", name, "' is not available along a flight");
      }
    }
    const Eigen::VectorXd c = gyrosid::compensate(*model_, d);
    out[ai].assign(c.data(), c.data() + c.size());
  }
  return out;
}

CofRun CofEvaluator::integrate(const std::array<std::vector<double>, 3>& rates, bool record_growth, std::size_t steps,
                               std::vector<StrapdownIns>* path) const {
  const std::size_t n = steps > 0 ? std::min(steps, excitation_.size()) : excitation_.size();
  const double dt = flight_.dt_s;
  StrapdownIns ins(flight_.initial(), dt);
  if (path) path->assign(1, ins), path->reserve(n + 1);
  CofRun r;
  const std::size_t stride = std::max<std::size_t>(1, n / 2000);
  const std::size_t hour = static_cast<std::size_t>(std::llround(3600.0 / dt));
  auto error_at = [&](std::size_t k) {
    const NavState& a = reference_path_[k];
    const NavState& b = ins.state();
    return earth::ned_offset(a.lat, a.lon, a.h, b.lat, b.lon, b.h);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d w(rates[0][k], rates[1][k], rates[2][k]);
    const Eigen::Vector3d e = w - excitation_.omega_ib_b[k];
    r.residual_mean += e;
    r.residual_rms += e.cwiseAbs2();
    ins.step(w * dt, flight_.dv[k]);
    if (path) path->push_back(ins);
    if (record_growth && ((k + 1) % stride == 0 || k + 1 == n)) {
      r.growth.push_back({excitation_.t_s[k], error_at(k + 1).norm()});
    }
    if (k + 1 == hour) r.error_after_1h_m = error_at(k + 1).norm();
  }
  r.residual_mean /= static_cast<double>(n);
  r.residual_rms = (r.residual_rms / static_cast<double>(n)).cwiseSqrt();
  r.error_ned = error_at(n);
  r.end_error_m = r.error_ned.norm();
  return r;
}

std::size_t CofEvaluator::steps_to(double at_s) const {
  const auto steps = static_cast<std::size_t>(std::llround(std::clamp(at_s, flight_.dt_s, duration_s()) / flight_.dt_s));
  return std::min(steps, excitation_.size());
}

Eigen::Vector3d CofEvaluator::position_error(const std::array<std::vector<double>, 3>& rates, double at_s) const {
  return integrate(rates, false, steps_to(at_s)).error_ned;
}

std::array<Eigen::Matrix3Xd, 3> CofEvaluator::position_error_gradient(const std::array<std::vector<double>, 3>& rates, double at_s) const {
  const std::size_t n = steps_to(at_s);
  const double dt = flight_.dt_s;
  std::vector<StrapdownIns> path;  // the INS before each step and after the last, as integrate runs it
  integrate(rates, false, n, &path);
  std::vector<Eigen::Vector3d> dtheta(n);
  for (std::size_t k = 0; k < n; ++k) dtheta[k] = Eigen::Vector3d(rates[0][k], rates[1][k], rates[2][k]) * dt;
  // d error_at(n) / d (lat, lon, h) of the INS by one-sided differences (6 mm, 1 mm): ned_offset is linear in
  // the end point's coordinates but for its radii and cosine at the mid-latitude.
  const NavState& a = reference_path_[n];
  const NavState& b = path.back().state();
  const auto offset = [&](double lat, double lon, double h) { return earth::ned_offset(a.lat, a.lon, a.h, lat, lon, h); };
  const Eigen::Vector3d e0 = offset(b.lat, b.lon, b.h);
  Eigen::Matrix3d out;
  out.col(0) = (offset(b.lat + 1e-9, b.lon, b.h) - e0) / 1e-9;
  out.col(1) = (offset(b.lat, b.lon + 1e-9, b.h) - e0) / 1e-9;
  out.col(2) = (offset(b.lat, b.lon, b.h + 1e-3) - e0) / 1e-3;
  const std::vector<Eigen::Matrix3d> by_increment = final_position_gradient(path, dtheta, flight_.dv, out);
  std::array<Eigen::Matrix3Xd, 3> gradient;
  for (int ax = 0; ax < 3; ++ax) {
    gradient[static_cast<std::size_t>(ax)].resize(3, static_cast<Eigen::Index>(n));
    for (std::size_t k = 0; k < n; ++k) gradient[static_cast<std::size_t>(ax)].col(static_cast<Eigen::Index>(k)) = by_increment[k].col(ax) * dt;
  }
  return gradient;
}

CofRun CofEvaluator::run(CompensationMode mode, bool noise, std::uint64_t seed, bool record_growth) const {
  const std::size_t n = excitation_.size();
  std::array<std::vector<double>, 3> measured = deterministic_;
  if (noise) {
    const char* names[] = {"gyro_x", "gyro_y", "gyro_z"};
    for (int a = 0; a < 3; ++a) {
      const auto ai = static_cast<std::size_t>(a);
      const GyroSensor& g = sensor_.gyros[ai];
      if (g.quantization_rad > 0 || std::isfinite(g.range_radps)) {
        // Quantization and saturation act on the noisy signal: run the sensor pipeline in full.
        measured[ai] = simulate_gyro(g, excitation_, c_s_b_[ai], seed, names[a]).rate_radps;
      } else {
        NoiseGenerator gen(g.noise, seed, names[a]);
        for (std::size_t k = 0; k < n; ++k) measured[ai][k] += gen.next(excitation_.t_s[k], flight_.dt_s);
      }
    }
  }
  switch (mode) {
    case CompensationMode::none: break;
    case CompensationMode::model:
      if (!model_ && !triad_) fail("criterion of fit: no model to compensate with");
      measured = compensate(measured);
      break;
    case CompensationMode::truth:
      for (int a = 0; a < 3; ++a) {
        const auto ai = static_cast<std::size_t>(a);
        for (std::size_t k = 0; k < n; ++k) {
          GyroEnvironment env;
          env.temp_c = excitation_.coil_temp_c[k];
          env.temp_rate_c_per_s = excitation_.coil_temp_rate_c_per_s[k];
          env.f_s = c_s_b_[ai] * excitation_.f_b[k];
          measured[ai][k] = sensor_.gyros[ai].errors.inverse(measured[ai][k], env);
        }
      }
      // The perfect compensation resolves the misalignment too: rates back into body axes.
      if (!measurement_matrix(sensor_.alignment).isIdentity(0.0)) {
        const Eigen::Matrix3d m_inv = measurement_matrix(sensor_.alignment).inverse();
        for (std::size_t k = 0; k < n; ++k) {
          const Eigen::Vector3d b = m_inv * Eigen::Vector3d(measured[0][k], measured[1][k], measured[2][k]);
          for (int a = 0; a < 3; ++a) measured[static_cast<std::size_t>(a)][k] = b(a);
        }
      }
      break;
  }
  return integrate(measured, record_growth);
}

CofRun CofEvaluator::run_reference(double white_sigma_1hz, double bias, std::uint64_t seed) const {
  const std::size_t n = excitation_.size();
  std::array<std::vector<double>, 3> rates;
  const double sigma = white_sigma_1hz / std::sqrt(flight_.dt_s);
  for (int a = 0; a < 3; ++a) {
    RandomStream random(seed, std::string("reference/") + "xyz"[a]);
    rates[static_cast<std::size_t>(a)].resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      rates[static_cast<std::size_t>(a)][k] = excitation_.omega_ib_b[k](a) + bias + (sigma > 0 ? sigma * random.normal() : 0.0);
    }
  }
  return integrate(rates, false);
}

Eigen::Vector3d CofEvaluator::decompose(const Eigen::Vector3d& e) const {
  const Eigen::Vector3d v = reference_path_.back().v_n;
  const Eigen::Vector3d along = v.norm() > 1e-9 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitX();
  Eigen::Vector3d cross_h = Eigen::Vector3d::UnitZ().cross(along);
  cross_h = cross_h.norm() > 1e-9 ? Eigen::Vector3d(cross_h.normalized()) : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d cross_v = along.cross(cross_h);
  return {e.dot(along), e.dot(cross_h), e.dot(cross_v)};
}

}  // namespace gyrosid::nav
