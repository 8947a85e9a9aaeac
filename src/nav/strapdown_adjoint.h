// The strapdown INS linearised about the path it flew, run backwards: the gradient of a linear function of
// its final position by the gyro increments of every step (the adjoint, or reverse mode, of the step).
// Perturbing the rates along one direction costs one INS run per direction; this costs about 36 steps per
// step for all directions and steps at once.
//
// With x_k the INS state before step k (StrapdownIns::StateVector) and u_k = delta-theta_k,
//   x_{k+1} = f(x_k, u_k),   F_k = d f / d x,   B_k = d f / d u,
//   lambda_n = [J 0],   d y / d u_k = lambda_{k+1} B_k,   lambda_k = lambda_{k+1} F_k,
// for y = J (lat, lon, h)_n. F_k and B_k are central differences of StrapdownIns::step itself, so the
// mechanisation keeps one definition; the steps' Jacobians are independent and computed in parallel, the
// backward recursion runs in a fixed order (bit-identical whatever the thread count).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "nav/strapdown.h"

namespace gyrosid::nav {

// d y / d u_k (3 x 3: y by the increment on each body axis, per rad) for k = 0 .. n-1. `path` holds the INS
// before each step and after the last (n + 1 states, as step left them); dtheta and dv the n steps'
// increments; `output_jacobian` d y / d (lat rad, lon rad, h m) at the end.
std::vector<Eigen::Matrix3d> final_position_gradient(const std::vector<StrapdownIns>& path, const std::vector<Eigen::Vector3d>& dtheta,
                                                     const std::vector<Eigen::Vector3d>& dv, const Eigen::Matrix3d& output_jacobian);

}  // namespace gyrosid::nav
