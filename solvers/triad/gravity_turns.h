// Hand turns known by gravity (reference=gravity): a triad turned by hand between static holds, with no
// rate table, as IMU-TK (Tedaldi, Pretto, Menegatti 2014) and Ferraris (1995) calibrate it. What is known
// of a turn is where gravity points before and after it: the mean specific force of the hold before, u_a,
// and of the hold after, u_b (unit vectors, body axes). The gyro outputs over the turn, compensated by the
// triad model, integrate to the turn's rotation
//
//   R = prod_k exp([omega_k dt_k]x),   omega_k = (I + M)^-1 (g_k - b(T_k))   (Earth rate neglected)
//
// (body at the turn's end -> body at its start), which carries gravity into the end frame: u_b = R' u_a. The
// residual u_b - R' u_a (dimensionless; two of its three components are independent - the turn about gravity
// itself is invisible) is one residual block per turn, in a group of its own (its own noise level). The
// holds' samples are the ordinary per-gyro rows with reference 0 (triad_problem.h); they fix the biases, the
// turns M.
//
// The residuals' covariance (the turn's weight). Each hold's direction is a mean of noisy specific force:
// per tangent axis its variance is s_a^2 / (n |a|^2), s_a^2 the per-sample accelerometer variance about the
// hold's mean, n its samples. A hold between two turns enters both: +du in the turn before it, -R' du in the turn
// after, so consecutive turns' residuals are correlated (Cov(r_h, r_h+1) = -Sigma_u R_h+1). The gyro noise over a
// turn adds s_g^2 sum dt^2 per axis of rotation error (s_g^2 the per-sample gyro variance in the holds). Each
// residual is taken in the tangent plane of u_after (its component along u_after is second order), and the 2T
// stacked residuals are whitened by the Cholesky factor of that block-tridiagonal covariance, evaluated once with
// R from the raw outputs less the holds' mean (the geometry only; the group's noise level is still estimated
// from the whitened residuals). Treating each hold's direction as exact and the turns as independent left the
// intervals 1.64x too narrow on 20 synthetic sessions (experiments/triad_misalignment/README.md).
//
// Recording layout: position_id 0 marks the samples in motion (their reference column is not read);
// every other position_id is a hold, and the reference must be 0 in it. A turn is the run of position_id 0
// between two holds; its samples k integrate over (t_{k-1}, t_k].
#pragma once

#include <Eigen/Core>

#include <vector>

#include "model/triad_model.h"
#include "solvers/nls/nls_problem.h"
#include "solvers/triad/triad_problem.h"

namespace gyrosid {

struct GravityTurn {
  std::vector<int> samples;    // in motion, in time order
  std::vector<double> dt;      // per sample, s
  Eigen::Vector3d before, after;  // unit specific-force directions of the holds around it
  double before_var = 0.0, after_var = 0.0;  // their variances per tangent axis, rad^2
  double angle_var = 0.0;                    // the gyro noise's rotation variance over the turn per axis, rad^2
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // R from the outputs less the holds' mean (geometry of the weights)
  double misfit_var = 0.0;  // what the noise does not explain, per tangent axis (turn_misfit_variance), rad^2
};

// The turns of a recording laid out as above (Error naming what is missing: accel columns, position_id, a
// hold with a non-zero reference, no turn between two holds).
std::vector<GravityTurn> gravity_turns(const TriadData& data);
// The holds' samples, one row each (position_id != 0).
TriadRows hold_rows(const TriadData& data);
// One residual block over every turn (2 residuals each, in the tangent planes) in `group`, over the misalignment
// and bias blocks of `layout`; whitened as above, or (whiten false) unweighted.
void add_gravity_turns(NlsProblem& problem, const TriadData& data, const std::vector<GravityTurn>& turns, const TriadProblemSpec& spec,
                       const TriadLayout& layout, int group, bool whiten = true);
// The turns' misfit beyond the noise at a model (an unweighted fit's): the mean squared tangent-plane residual per
// axis less the mean variance the noise predicts, at least 0. A real hand-held session is not a noise-only process
// (Earth rate neglected, a hand is not a rigid rotation): on IMU-TK's Xsens session the turns' residuals are ~50
// times what the holds' noise predicts, and whitening by the noise alone mis-weights them (the fit failed); this
// term, added to every turn's variance, keeps the weights honest there and vanishes on noise-only data.
double turn_misfit_variance(const TriadData& data, const std::vector<GravityTurn>& turns, const TriadModel& model, int bias_order);

}  // namespace gyrosid
