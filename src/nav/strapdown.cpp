#include "nav/strapdown.h"

#include <cmath>

#include "core/earth_model.h"

namespace gyrosid::nav {

using namespace earth;

Eigen::Quaterniond rotation_vector_quaternion(const Eigen::Vector3d& phi) {
  const double a2 = phi.squaredNorm();
  // sin(a/2)/a by its series below 1e-4 rad (relative error < 1e-18), exact above.
  double s, c;
  if (a2 < 1e-8) {
    s = 0.5 - a2 / 48.0;
    c = 1.0 - a2 / 8.0;
  } else {
    const double a = std::sqrt(a2);
    s = std::sin(0.5 * a) / a;
    c = std::cos(0.5 * a);
  }
  return Eigen::Quaterniond(c, s * phi.x(), s * phi.y(), s * phi.z());
}

StrapdownIns::StrapdownIns(const NavState& initial, double dt_s) : s_(initial), dt_(dt_s), prev_v_n_(initial.v_n) {}

void StrapdownIns::step(const Eigen::Vector3d& dtheta, const Eigen::Vector3d& dv) {
  // Two-sample coning and sculling use the previous interval's increments (none on the first step).
  const Eigen::Vector3d pth = first_ ? Eigen::Vector3d::Zero() : prev_dtheta_;
  const Eigen::Vector3d pdv = first_ ? Eigen::Vector3d::Zero() : prev_dv_;
  const Eigen::Vector3d phi = dtheta + pth.cross(dtheta) / 12.0;
  // Rotation compensation to third order (exact to O(dt^4) for a constant rate and specific force:
  // integral of exp([w x] t) f = dv + dth x dv / 2 + dth x (dth x dv) / 6 + ...) plus two-sample sculling.
  const Eigen::Vector3d dv_b = dv + 0.5 * dtheta.cross(dv) + dtheta.cross(dtheta.cross(dv)) / 6.0 +
                               (pth.cross(dv) + pdv.cross(dtheta)) / 12.0;

  // Mid-interval navigation quantities: velocity extrapolated half a step, position moved half a step with
  // it. (The vertical channel is unstable; gravity taken at the start of the step would be a bias of
  // (dg/dh) v_D dt / 2 that it amplifies over hours.)
  const Eigen::Vector3d v_mid = first_ ? s_.v_n : Eigen::Vector3d(s_.v_n + 0.5 * (s_.v_n - prev_v_n_));
  const EarthRadii r0 = radii(s_.lat);
  const double h_mid = s_.h - 0.5 * v_mid.z() * dt_;
  const double lat_mid = s_.lat + 0.5 * v_mid.x() / (r0.meridian + h_mid) * dt_;
  const EarthRadii r = radii(lat_mid);
  const Eigen::Vector3d w_ie = earth_rate_n(lat_mid);
  const Eigen::Vector3d w_en = transport_rate_n(lat_mid, h_mid, v_mid, r);
  const Eigen::Vector3d zeta = (w_ie + w_en) * dt_;

  // Velocity.
  const Eigen::Matrix3d c_n_b = s_.q_n_b.toRotationMatrix();
  const Eigen::Vector3d dv_sf = c_n_b * dv_b - 0.5 * zeta.cross(c_n_b * dv_b);
  const Eigen::Vector3d dv_cor = (gravity_n(lat_mid, h_mid) - (2.0 * w_ie + w_en).cross(v_mid)) * dt_;
  const Eigen::Vector3d v_old = s_.v_n;
  s_.v_n = v_old + dv_sf + dv_cor;

  // Position from the mean velocity, radii at mid-latitude.
  const Eigen::Vector3d v_avg = 0.5 * (v_old + s_.v_n);
  const double h_new = s_.h - v_avg.z() * dt_;
  const double h_avg = 0.5 * (s_.h + h_new);
  const double lat_new_est = s_.lat + v_avg.x() / (r.meridian + h_avg) * dt_;
  const double lat_avg = 0.5 * (s_.lat + lat_new_est);
  const EarthRadii ra = radii(lat_avg);
  const double lat_new = s_.lat + v_avg.x() / (ra.meridian + h_avg) * dt_;
  s_.lon += v_avg.y() / ((ra.transverse + h_avg) * std::cos(lat_avg)) * dt_;
  s_.lat = lat_new;
  s_.h = h_new;

  // Attitude: body rotation phi, navigation-frame rotation zeta.
  s_.q_n_b = rotation_vector_quaternion(-zeta) * s_.q_n_b * rotation_vector_quaternion(phi);
  s_.q_n_b.normalize();

  prev_v_n_ = v_old;
  prev_dtheta_ = dtheta;
  prev_dv_ = dv;
  first_ = false;
  t_ += dt_;
}

void StrapdownIns::perturb(const StateVector& dx) {
  s_.lat += dx(0), s_.lon += dx(1), s_.h += dx(2);
  s_.v_n += dx.segment<3>(3);
  s_.q_n_b = rotation_vector_quaternion(dx.segment<3>(6)) * s_.q_n_b;
  prev_v_n_ += dx.segment<3>(9);
  prev_dtheta_ += dx.segment<3>(12);
}

StrapdownIns::StateVector StrapdownIns::minus(const StrapdownIns& other) const {
  StateVector d;
  d << s_.lat - other.s_.lat, s_.lon - other.s_.lon, s_.h - other.s_.h, s_.v_n - other.s_.v_n, Eigen::Vector3d::Zero(),
      prev_v_n_ - other.prev_v_n_, prev_dtheta_ - other.prev_dtheta_;
  // q(dx) = q_this q_other^-1; its rotation vector is 2 vec(q) to first order (sign fixed by w >= 0).
  Eigen::Quaterniond e = s_.q_n_b * other.s_.q_n_b.conjugate();
  if (e.w() < 0) e.coeffs() = -e.coeffs();
  d.segment<3>(6) = 2.0 * e.vec();
  return d;
}

}  // namespace gyrosid::nav
