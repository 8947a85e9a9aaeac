// A planted RBF problem for solver tests: five Gaussian nodes of width 0.3 sampled noise-free on a 21 x 21
// grid over [-1, 1]^2 (centres on grid points), in the network's own coordinates.
#pragma once

#include <cmath>

#include "solvers/solver.h"

namespace gyrosid::testing_support {

// Five Gaussian nodes of width 0.3 on a 21 x 21 grid over [-1, 1]^2 (centres on grid points).
struct Planted {
  double c[5][2] = {{-0.6, -0.6}, {0.2, -0.4}, {0.6, 0.6}, {-0.4, 0.4}, {0.0, 0.0}};
  double w[5] = {1.0, -0.7, 0.5, 0.8, -0.4};
  double r = 0.3;
  double operator()(double a, double b) const {
    double s = 0;
    for (int j = 0; j < 5; ++j) {
      const double u = (a - c[j][0]) / r, v = (b - c[j][1]) / r;
      s += w[j] * std::exp(-u * u - v * v);
    }
    return s;
  }
};

inline RbfProblem planted_problem() {
  const Planted f;
  const int g = 21;
  RbfProblem p;
  p.features = {"a", "b"};
  p.normalizer = Normalizer{Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2)};
  p.x.resize(g * g, 2);
  p.y.resize(g * g);
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const double a = -1 + 2.0 * i / (g - 1), b = -1 + 2.0 * j / (g - 1);
      p.x(i * g + j, 0) = a, p.x(i * g + j, 1) = b, p.y(i * g + j) = f(a, b);
    }
  return p;
}

}  // namespace gyrosid::testing_support
