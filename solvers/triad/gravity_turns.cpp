#include "solvers/triad/gravity_turns.h"

#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>

#include "core/error.h"

namespace gyrosid {
namespace {

bool moving(const TriadData& d, std::size_t k) { return d.position_id[k] == 0; }

// The mean specific-force direction of samples [begin, end).
Eigen::Vector3d gravity_direction(const TriadData& d, std::size_t begin, std::size_t end) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = begin; k < end; ++k) sum += d.accel.row(static_cast<Eigen::Index>(k)).transpose();
  if (!(sum.norm() > 0.0)) fail("triad: reference=gravity: the hold ending at sample ", end, " has no specific force");
  return sum.normalized();
}

// One turn: u_after - R' u_before, R the compensated outputs integrated (gravity_turns.h). Parameter blocks:
// the three rows of M, then the three bias polynomials (coefficients of v^0..v^nb).
class GravityTurnCost {
 public:
  GravityTurnCost(const TriadData& d, const GravityTurn& turn, const TriadBias& scaling, int bias_order)
      : turn_(turn), bias_order_(bias_order), gyro_(static_cast<Eigen::Index>(turn.samples.size()), 3),
        v_(static_cast<Eigen::Index>(turn.samples.size()), 3) {
    for (std::size_t s = 0; s < turn.samples.size(); ++s) {
      const auto k = static_cast<Eigen::Index>(turn.samples[s]);
      gyro_.row(static_cast<Eigen::Index>(s)) = d.gyro.row(k);
      for (int a = 0; a < 3; ++a) v_(static_cast<Eigen::Index>(s), a) = scaling.normalised(d.temp_c(k, a));
    }
  }

  template <typename T>
  bool operator()(T const* const* p, T* residual) const {
    Eigen::Matrix<T, 3, 3> a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = p[i][j] + T(i == j ? 1.0 : 0.0);
    const Eigen::Matrix<T, 3, 3> inverse = a.inverse();
    Eigen::Matrix<T, 3, 3> r = Eigen::Matrix<T, 3, 3>::Identity();
    for (Eigen::Index s = 0; s < gyro_.rows(); ++s) {
      Eigen::Matrix<T, 3, 1> g;
      for (int i = 0; i < 3; ++i) {
        T b = T(0.0), vp = T(1.0);
        for (int o = 0; o <= bias_order_; ++o, vp *= T(v_(s, i))) b += p[3 + i][o] * vp;
        g(i) = T(gyro_(s, i)) - b;
      }
      const Eigen::Matrix<T, 3, 1> angle = inverse * g * T(turn_.dt[static_cast<std::size_t>(s)]);
      Eigen::Matrix<T, 3, 3> step;
      ceres::AngleAxisToRotationMatrix(angle.data(), step.data());
      r = (r * step).eval();
    }
    const Eigen::Matrix<T, 3, 1> predicted = r.transpose() * turn_.before.cast<T>();
    for (int i = 0; i < 3; ++i) residual[i] = predicted(i) - T(turn_.after(i));
    return true;
  }

 private:
  GravityTurn turn_;
  int bias_order_;
  Eigen::MatrixX3d gyro_, v_;
};

}  // namespace

std::vector<GravityTurn> gravity_turns(const TriadData& d) {
  if (d.position_id.empty()) fail("triad: reference=gravity needs position_id (0 in motion, a hold's own id otherwise)");
  if (!d.has_accel() || !d.accel.allFinite()) fail("triad: reference=gravity needs accel_{x,y,z}_mps2 at every sample");
  const auto n = static_cast<std::size_t>(d.size());
  std::vector<std::pair<std::size_t, std::size_t>> holds;
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin;
    while (end < n && d.position_id[end] == d.position_id[begin]) ++end;
    if (!moving(d, begin)) {
      if (!d.reference.middleRows(static_cast<Eigen::Index>(begin), static_cast<Eigen::Index>(end - begin)).isZero(0.0)) {
        fail("triad: reference=gravity: the hold at samples ", begin, "..", end - 1, " (position_id ", d.position_id[begin], ") has a non-zero reference rate");
      }
      holds.emplace_back(begin, end);
    }
    begin = end;
  }
  std::vector<GravityTurn> turns;
  for (std::size_t h = 0; h + 1 < holds.size(); ++h) {
    GravityTurn turn;
    for (std::size_t k = holds[h].second; k < holds[h + 1].first; ++k) {
      if (!moving(d, k)) continue;
      turn.samples.push_back(static_cast<int>(k));
      turn.dt.push_back(d.t_s[k] - d.t_s[k - 1]);
    }
    if (turn.samples.empty()) fail("triad: reference=gravity: no samples in motion (position_id 0) between the holds ending at sample ", holds[h].second - 1, " and starting at ", holds[h + 1].first);
    turn.before = gravity_direction(d, holds[h].first, holds[h].second);
    turn.after = gravity_direction(d, holds[h + 1].first, holds[h + 1].second);
    turns.push_back(std::move(turn));
  }
  // Two independent constraints per turn (the turn about gravity is invisible): the nine entries of M need five.
  if (turns.size() < 5) {
    fail("triad: reference=gravity: ", turns.size(), " turns between ", holds.size(), " holds give ", 2 * turns.size(),
         " constraints for the 9 entries of M - at least 5 turns are needed");
  }
  return turns;
}

TriadRows hold_rows(const TriadData& d) {
  TriadRows rows;
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    if (!moving(d, static_cast<std::size_t>(k))) rows.add_sample(static_cast<int>(k));
  }
  return rows;
}

void add_gravity_turns(NlsProblem& p, const TriadData& d, const std::vector<GravityTurn>& turns, const TriadProblemSpec& spec,
                       const TriadLayout& layout, int group) {
  std::vector<int> blocks(layout.misalignment.begin(), layout.misalignment.end());
  blocks.insert(blocks.end(), layout.bias.begin(), layout.bias.end());
  for (const GravityTurn& turn : turns) {
    auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<GravityTurnCost, 4>>(new GravityTurnCost(d, turn, spec.start.bias, spec.bias_order));
    for (int b : blocks) cost->AddParameterBlock(p.block(b).size());
    cost->SetNumResiduals(3);
    p.add_residual(std::move(cost), blocks, group);
  }
}

}  // namespace gyrosid
