// The misalignment chain of a gyro triad (thesis s3.4, figs 3.2, 3.14, 3.15):
//
//   input axis (IA) --T_RA_IA(two angles)--> reference/case axes (RA) --T_CA_RA(orientation)--> cluster axes
//   (CA) --T_B_CA(two insertion angles)--> body axes (B),      T_B_IA = T_B_CA T_CA_RA T_RA_IA  (eq 3.56)
//
// Angles (rad), per gyro i in {x, y, z} as in the thesis: IA->RA (phi, theta, psi)_{x,y} (eqs 3.57-3.59)
// and insertion (mu, eta, xi)_{x,y} (eqs 3.60-3.62). Each pair rotates the gyro's sensing axis about the
// two axes perpendicular to it: T(a_x, a_y) = R_x(a_x) R_y(a_y) in the gyro's own RA frame, so that
// T e_z = (sin a_y, -sin a_x cos a_y, cos a_x cos a_y) - eq 3.13 (whose minus signs the text extraction
// lost). T_CA_RA is the cyclic permutation that puts the gyro's RA z axis on cluster axis i (table 3.1).
//
// Gyro i measures the body rate along its input axis u_i = T_B_IA_i e_z, so the triad's measurement matrix
// is M with rows u_i^T: omega_meas = M omega_ib_b. To first order in the angles (eq 3.72)
//
//        [ 1                 phi_y + mu_y      -(phi_x + mu_x)   ]
//   M  = [ -(theta_x + eta_x)   1               theta_y + eta_y  ]
//        [ psi_y + xi_y      -(psi_x + xi_x)     1               ]
//
// Only the sums (IA angle + insertion angle) are observable - six combined parameters, as in eq 3.72.
// Note: the thesis builds its compensation by summing T_B_IA_i * omega_i, i.e. M^T; the exact inverse is
// M^{-1}, and M^T differs from it at first order by the symmetric (non-orthogonality) part of M - I.
#pragma once

#include <Eigen/Core>

#include <array>

#include "core/rotation.h"

namespace gyrosid {

struct GyroAlignment {
  double ia_x = 0.0, ia_y = 0.0;                // IA -> RA: phi/theta/psi (x, y)
  double insertion_x = 0.0, insertion_y = 0.0;  // CA -> B: mu/eta/xi (x, y)
};

Eigen::Matrix3d ra_from_ia(double angle_x, double angle_y);   // T_RA_IA, exact
Eigen::Matrix3d ca_from_ra(int axis);                         // T_CA_RA for the gyro on cluster axis 0/1/2
Eigen::Matrix3d body_from_ca(int axis, double angle_x, double angle_y);  // T_B_CA of gyro `axis`, exact
Eigen::Matrix3d body_from_ia(int axis, const GyroAlignment& a);          // T_B_IA (eq 3.56)

// Measurement matrix of a triad, exact (rows: input axes in body) and to first order (eq 3.72).
Eigen::Matrix3d measurement_matrix(const std::array<GyroAlignment, 3>& alignment);
Eigen::Matrix3d measurement_matrix_small_angle(const std::array<GyroAlignment, 3>& alignment);

}  // namespace gyrosid
