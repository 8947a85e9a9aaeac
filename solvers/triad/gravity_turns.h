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
};

// The turns of a recording laid out as above (Error naming what is missing: accel columns, position_id, a
// hold with a non-zero reference, no turn between two holds).
std::vector<GravityTurn> gravity_turns(const TriadData& data);
// The holds' samples, one row each (position_id != 0).
TriadRows hold_rows(const TriadData& data);
// One residual block per turn in `group`, over the misalignment and bias blocks of `layout`.
void add_gravity_turns(NlsProblem& problem, const TriadData& data, const std::vector<GravityTurn>& turns, const TriadProblemSpec& spec,
                       const TriadLayout& layout, int group);

}  // namespace gyrosid
