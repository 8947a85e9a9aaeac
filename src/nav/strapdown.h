// Strapdown inertial navigation in local geographic (NED) axes, WGS-84 Earth (Titterton & Weston ch. 3,
// thesis appendix D fig D.1), driven by the integrated IMU outputs of each step (delta-theta, delta-v in
// body axes):
//   attitude  q_n_b(k) = q(-zeta) * q_n_b(k-1) * q(phi),  phi = dtheta_k + dtheta_{k-1} x dtheta_k / 12
//             (two-sample coning), zeta = (omega_ie_n + omega_en_n) dt (navigation-frame rotation)
//   velocity  dv_b = dv_k + dtheta_k x dv_k / 2 + (dtheta_{k-1} x dv_k + dv_{k-1} x dtheta_k) / 12
//             (rotation compensation + two-sample sculling);
//             v_n(k) = v_n(k-1) + (I - [zeta x]/2) C_n_b(k-1) dv_b + (g_n - (2 omega_ie_n + omega_en_n) x v_n) dt
//             (Coriolis and gravity at mid-interval)
//   position  latitude, longitude, height from the mean velocity with mid-interval radii.
// No altitude aiding: the vertical channel is free (and unstable), as in the thesis.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/nav_state.h"

namespace gyrosid::nav {

using gyrosid::NavState;

class StrapdownIns {
 public:
  StrapdownIns(const NavState& initial, double dt_s);
  // One step with this interval's body-axis integrals (rad, m/s).
  void step(const Eigen::Vector3d& dtheta, const Eigen::Vector3d& dv);
  const NavState& state() const { return s_; }
  double time_s() const { return t_; }

  // Its state as a vector, for linearising the step (strapdown_adjoint.h): latitude, longitude (rad), height
  // (m), v_n (m/s), a small rotation of the computed navigation frame (rad, NED: q_n_b -> q(dx) q_n_b), and
  // the memory of the two-sample algorithms the gyros reach: the previous step's v_n and delta-theta.
  static constexpr int kStateSize = 15;
  using StateVector = Eigen::Matrix<double, kStateSize, 1>;
  void perturb(const StateVector& dx);
  // This state minus `other`'s, in the coordinates of perturb (the attitude to first order).
  StateVector minus(const StrapdownIns& other) const;

 private:
  NavState s_;
  double dt_;
  double t_ = 0.0;
  Eigen::Vector3d prev_dtheta_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_dv_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_v_n_;
  bool first_ = true;
};

// Quaternion of the rotation vector phi (exact: axis phi/|phi|, angle |phi|).
Eigen::Quaterniond rotation_vector_quaternion(const Eigen::Vector3d& phi);

}  // namespace gyrosid::nav
