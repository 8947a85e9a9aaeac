#include "nav/strapdown_adjoint.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

#include "core/parallel.h"

namespace gyrosid::nav {
namespace {

using State = StrapdownIns::StateVector;
constexpr int kN = StrapdownIns::kStateSize;

// Central-difference steps per state coordinate, powers of two so that a coordinate plus its step is exact:
// 0.7 m of position (2^-23 rad), 0.5 m of height, 8 mm/s, 1 urad of attitude, 7.5 nrad of increment. The
// Jacobians of a step are I plus couplings of order dt; a rounding error of ulp/h in them, repeated over
// 10^4-10^5 steps, is what the steps must keep small, while the central differences leave a truncation of
// order h^2. (One-sided differences with steps of 1 nrad and 0.1 mm/s were off by 1e-4 relative; these agree
// with central differences of the whole INS to 2e-8 - 3e-6, tests/nav/test_cof.cpp.)
State state_steps() {
  State h;
  h << 0x1p-23, 0x1p-23, 0x1p-1, 0x1p-7, 0x1p-7, 0x1p-7, 0x1p-20, 0x1p-20, 0x1p-20, 0x1p-7, 0x1p-7, 0x1p-7, 0x1p-27, 0x1p-27, 0x1p-27;
  return h;
}
constexpr double kIncrementStep = 0x1p-27;

struct StepJacobians {
  Eigen::Matrix<double, kN, kN> f;
  Eigen::Matrix<double, kN, 3> b;
};

StepJacobians step_jacobians(const StrapdownIns& before, const StrapdownIns& after, const Eigen::Vector3d& dtheta, const Eigen::Vector3d& dv,
                             const State& h) {
  const auto moved = [&](const State& dx, const Eigen::Vector3d& du) {
    StrapdownIns ins = before;
    ins.perturb(dx);
    ins.step(dtheta + du, dv);
    return ins.minus(after);
  };
  StepJacobians j;
  for (int i = 0; i < kN; ++i) {
    const State dx = State::Unit(i) * h(i);
    j.f.col(i) = (moved(dx, Eigen::Vector3d::Zero()) - moved(-dx, Eigen::Vector3d::Zero())) / (2.0 * h(i));
  }
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d du = Eigen::Vector3d::Unit(a) * kIncrementStep;
    j.b.col(a) = (moved(State::Zero(), du) - moved(State::Zero(), -du)) / (2.0 * kIncrementStep);
  }
  return j;
}

}  // namespace

std::vector<Eigen::Matrix3d> final_position_gradient(const std::vector<StrapdownIns>& path, const std::vector<Eigen::Vector3d>& dtheta,
                                                     const std::vector<Eigen::Vector3d>& dv, const Eigen::Matrix3d& output_jacobian) {
  const std::size_t n = dtheta.size();
  if (path.size() != n + 1 || dv.size() < n) throw std::invalid_argument("final_position_gradient: path, increments and steps disagree");
  std::vector<Eigen::Matrix3d> gradient(n);
  Eigen::Matrix<double, 3, kN> lambda = Eigen::Matrix<double, 3, kN>::Zero();
  lambda.leftCols<3>() = output_jacobian;
  const State h = state_steps();
  // Backwards in blocks: a block's Jacobians in parallel, then the recursion through it.
  constexpr std::size_t kBlock = 1024;
  std::vector<StepJacobians> block(kBlock);
  for (std::size_t end = n; end > 0;) {
    const std::size_t begin = end > kBlock ? end - kBlock : 0;
    parallel_for(static_cast<std::ptrdiff_t>(end - begin), [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      for (std::ptrdiff_t i = b; i < e; ++i) {
        const std::size_t k = begin + static_cast<std::size_t>(i);
        block[static_cast<std::size_t>(i)] = step_jacobians(path[k], path[k + 1], dtheta[k], dv[k], h);
      }
    }, 64);
    for (std::size_t k = end; k-- > begin;) {
      const StepJacobians& j = block[k - begin];
      gradient[k] = lambda * j.b;
      lambda = lambda * j.f;
    }
    end = begin;
  }
  return gradient;
}

}  // namespace gyrosid::nav
