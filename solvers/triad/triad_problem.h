// The triad model (model/triad_model.h) as one least-squares problem (solvers/nls):
//
//   r_ia = sum_k w_ak [ (I + M) omega_k + b(T_k) + G f_k + e(T_k, g_k) - g_k ]_i
//
// one residual group per gyro i (its own noise level), one row a per sample (rate reference: w = 1), or,
// with the angle reference (Ferraris's known rotations between static positions), one row per turning
// segment of constant position_id - its integral, w_ak = dt_k / sqrt(sum dt^2), so it carries one sample's
// noise - and one row per sample of a static hold (a segment whose reference is zero throughout). Parameter blocks per gyro i, in priority order for the observability analysis:
//   misalignment_i (row i of M) | bias_i (c_i0..c_inb) | g_sensitivity_i (row i of G) | surface_i linear
//   coefficients | surface_i nodes.
// A surface with a weight penalty adds its rows P w - t (SurfaceTerm::weight_penalty: the fitter's ridge, the
// surface's share of M_ii's and b's columns held) to the gyro's group. Each gyro's equation involves only its own blocks, so the groups are independent least-squares problems
// posed together (their covariances do not mix noise levels).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "model/triad_model.h"
#include "solvers/nls/nls_problem.h"
#include "solvers/triad/surface_terms.h"

namespace gyrosid {

// Rows of the problem as weighted sums of samples (CSR): row a covers entries [start[a], start[a+1]).
struct TriadRows {
  std::vector<int> start{0};
  std::vector<int> sample;
  std::vector<double> weight;
  std::string description;
  int rows() const { return static_cast<int>(start.size()) - 1; }
  // One row of its own: sample k, weight 1.
  void add_sample(int k) {
    sample.push_back(k);
    weight.push_back(1.0);
    start.push_back(static_cast<int>(sample.size()));
  }
};

TriadRows rate_rows(const TriadData& data);
// Angle reference (Error when the recording has no position_id).
TriadRows angle_rows(const TriadData& data);

struct TriadProblemSpec {
  int bias_order = 0;
  bool g_sensitivity = false;
  TriadModel start;  // initial values of M, b (its reference and scale define v), G; surfaces unused
  std::array<const SurfaceTerm*, 3> surfaces{nullptr, nullptr, nullptr};
  // The rate (rad/s, N x 3) each gyro's surface is evaluated at, per sample; null: the recorded outputs. The
  // recorded output carries the very noise the rows fit, so a surface of it (a rate polynomial most of all)
  // can spend coefficients on that noise (errors in variables); triad_fit passes the outputs with their
  // noise averaged down instead (surface_input=smoothed, triad_fit.h).
  const Eigen::MatrixX3d* surface_rate = nullptr;
  double surface_rate_at(const TriadData& d, Eigen::Index k, int axis) const { return surface_rate ? (*surface_rate)(k, axis) : d.gyro(k, axis); }
};

// Block indices of the problem, per gyro (-1: absent).
struct TriadLayout {
  std::array<int, 3> misalignment{-1, -1, -1}, bias{-1, -1, -1}, g_sensitivity{-1, -1, -1}, surface{-1, -1, -1};
  std::array<std::vector<int>, 3> nodes;
};

NlsProblem build_triad_problem(const TriadData& data, const TriadRows& rows, const TriadProblemSpec& spec, TriadLayout& layout);
// The model at the problem's current values (surfaces built by the spec's terms).
TriadModel triad_model_of(const NlsProblem& problem, const TriadLayout& layout, const TriadProblemSpec& spec);

}  // namespace gyrosid
