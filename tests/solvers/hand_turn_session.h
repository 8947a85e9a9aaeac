// The synthetic hand-turned session of the reference=gravity tests (solvers/triad/gravity_turns.h), shared by
// the triad fit's tests and the command's.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <random>
#include <vector>

#include "core/units.h"
#include "model/triad_model.h"

namespace gyrosid::testing_support {

// A hand-turned session (reference=gravity): 14 holds of 1 s at random attitudes (Earth rate neglected,
// specific force up), 13 turns of 1.5 s between them at constant rate; white noise on the gyro outputs and on the
// holds' specific force (per sample, rad/s and m/s^2).
inline TriadData hand_turn_session(const Eigen::Matrix3d& m, const Eigen::Vector3d& bias, std::uint64_t seed, double gyro_noise, double accel_noise) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto random_rotation = [&] { return Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix(); };
  auto noise = [&](double sigma) { return Eigen::Vector3d(sigma * normal(rng), sigma * normal(rng), sigma * normal(rng)); };
  TriadData d;
  std::vector<Eigen::Vector3d> out, accel;
  std::vector<int> id;
  Eigen::Matrix3d c = random_rotation();  // body -> nav
  const double dt = 0.01;
  for (int h = 1; h <= 14; ++h) {
    for (int k = 0; k < 100; ++k) {
      out.push_back(bias + noise(gyro_noise));
      accel.push_back(c.transpose() * Eigen::Vector3d(0, 0, -9.81) + noise(accel_noise));
      id.push_back(h);
    }
    if (h == 14) break;
    const Eigen::Matrix3d next = random_rotation();
    const Eigen::AngleAxisd turn(c.transpose() * next);  // body rotation from this hold to the next
    const int samples = 150;
    const Eigen::Vector3d omega = turn.axis() * turn.angle() / (samples * dt);
    for (int k = 0; k < samples; ++k) {
      out.push_back((Eigen::Matrix3d::Identity() + m) * omega + bias + noise(gyro_noise));
      accel.push_back(Eigen::Vector3d::Zero());  // not read in motion
      id.push_back(0);
    }
    c = next;
  }
  const auto n = static_cast<Eigen::Index>(out.size());
  d.gyro.resize(n, 3);
  d.accel.resize(n, 3);
  d.reference = Eigen::MatrixX3d::Zero(n, 3);
  d.temp_c = Eigen::MatrixX3d::Constant(n, 3, 25.0);
  for (Eigen::Index k = 0; k < n; ++k) {
    d.t_s.push_back(static_cast<double>(k) * dt);
    d.gyro.row(k) = out[static_cast<std::size_t>(k)].transpose();
    d.accel.row(k) = accel[static_cast<std::size_t>(k)].transpose();
    d.position_id.push_back(id[static_cast<std::size_t>(k)]);
  }
  return d;
}

// The planted triad of the hand-turn tests: M (scale factors -5e-3..1e-2, misalignments up to 3 mrad) and biases.
inline Eigen::Matrix3d hand_turn_misalignment() {
  Eigen::Matrix3d m;
  m << 2e-3, -1e-3, 3e-3, 8e-4, -5e-3, 1.4e-3, 4e-4, -1e-3, 1e-2;
  return m;
}
inline Eigen::Vector3d hand_turn_bias() { return {units::dph_to_radps(-15.0), units::dph_to_radps(7.0), units::dph_to_radps(22.0)}; }

}  // namespace gyrosid::testing_support
