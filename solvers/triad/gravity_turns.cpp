#include "solvers/triad/gravity_turns.h"

#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
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

// Per-sample variance of the columns of x over [begin, end) about their mean, averaged over the columns.
double sample_variance(const Eigen::MatrixX3d& x, std::size_t begin, std::size_t end) {
  if (end - begin < 2) return 0.0;
  const auto b = static_cast<Eigen::Index>(begin), n = static_cast<Eigen::Index>(end - begin);
  const Eigen::RowVector3d mean = x.middleRows(b, n).colwise().mean();
  return (x.middleRows(b, n).rowwise() - mean).squaredNorm() / (3.0 * static_cast<double>(n - 1));
}

// An orthonormal basis (3 x 2) of the plane perpendicular to the unit vector u.
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& u) {
  const Eigen::Vector3d a = std::abs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> b;
  b.col(0) = u.cross(a).normalized();
  b.col(1) = u.cross(b.col(0));
  return b;
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

  static constexpr int kFirstBiasBlock = 3;  // p[0..2]: M's rows; p[kFirstBiasBlock + axis]: the axis's bias

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
        for (int o = 0; o <= bias_order_; ++o, vp *= T(v_(s, i))) b += p[kFirstBiasBlock + i][o] * vp;
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

// Every turn's residual in the tangent plane of its u_after, stacked (2T) and whitened: W (B' r), W = L^-1 of the
// stacked covariance (gravity_turns.h).
class AllTurnsCost {
 public:
  AllTurnsCost(std::vector<GravityTurnCost> turns, std::vector<Eigen::Matrix<double, 3, 2>> bases, Eigen::MatrixXd whitening)
      : turns_(std::move(turns)), bases_(std::move(bases)), whitening_(std::move(whitening)) {}
  template <typename T>
  bool operator()(T const* const* p, T* residual) const {
    const auto n = static_cast<Eigen::Index>(2 * turns_.size());
    Eigen::Matrix<T, Eigen::Dynamic, 1> r(n);
    for (std::size_t h = 0; h < turns_.size(); ++h) {
      T r3[3];
      if (!turns_[h](p, r3)) return false;
      const Eigen::Matrix<T, 3, 1> v(r3[0], r3[1], r3[2]);
      r.template segment<2>(static_cast<Eigen::Index>(2 * h)) = bases_[h].transpose().cast<T>() * v;
    }
    Eigen::Map<Eigen::Matrix<T, Eigen::Dynamic, 1>>(residual, n) = whitening_.cast<T>() * r;
    return true;
  }

 private:
  std::vector<GravityTurnCost> turns_;
  std::vector<Eigen::Matrix<double, 3, 2>> bases_;
  Eigen::MatrixXd whitening_;
};

// The noise covariance (3 x 3) of one turn's residual u_after - R' u_before: the two holds' direction scatter
// (each in the plane perpendicular to its direction, R' carrying the one before) and the gyro noise integrated
// over the turn (perpendicular to R' u_before).
Eigen::Matrix3d turn_noise_covariance(const GravityTurn& g) {
  const Eigen::Matrix3d eye = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d v = g.rotation.transpose() * g.before;
  return g.after_var * (eye - g.after * g.after.transpose()) +
         g.rotation.transpose() * (g.before_var * (eye - g.before * g.before.transpose())) * g.rotation +
         g.angle_var * (eye - v * v.transpose());
}

// The stacked tangent-plane residuals' covariance (2T x 2T, block tridiagonal) and its whitening L^-1.
Eigen::MatrixXd turn_whitening(const std::vector<GravityTurn>& turns, const std::vector<Eigen::Matrix<double, 3, 2>>& bases) {
  const auto t = static_cast<Eigen::Index>(turns.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(2 * t, 2 * t);
  const Eigen::Matrix3d eye = Eigen::Matrix3d::Identity();
  for (Eigen::Index h = 0; h < t; ++h) {
    const GravityTurn& g = turns[static_cast<std::size_t>(h)];
    const Eigen::Matrix3d cov_after = g.after_var * (eye - g.after * g.after.transpose());
    const auto& b = bases[static_cast<std::size_t>(h)];
    c.block<2, 2>(2 * h, 2 * h) = b.transpose() * turn_noise_covariance(g) * b + g.misfit_var * Eigen::Matrix2d::Identity();
    if (h + 1 < t) {  // the hold after turn h is the hold before turn h + 1: Cov(r_h, r_h+1) = -Sigma_u R_h+1
      const GravityTurn& next = turns[static_cast<std::size_t>(h + 1)];
      const Eigen::Matrix2d cross = b.transpose() * (-cov_after * next.rotation) * bases[static_cast<std::size_t>(h + 1)];
      c.block<2, 2>(2 * h, 2 * h + 2) = cross;
      c.block<2, 2>(2 * h + 2, 2 * h) = cross.transpose();
    }
  }
  // Noise-free recordings (no scatter in any hold): equal weights. Otherwise a ridge far below every variance.
  const double scale = c.diagonal().maxCoeff();
  if (!(scale > 0.0)) c.setIdentity();
  else c.diagonal().array() += 1e-9 * scale;
  const Eigen::LLT<Eigen::MatrixXd> llt(c);
  if (llt.info() != Eigen::Success) fail("triad: reference=gravity: the turns' residual covariance is not positive definite");
  Eigen::MatrixXd l = llt.matrixL();
  // Scaled so that the whitened residuals keep the raw ones' size (unit vectors' differences): the solve sums the
  // groups' squares as they are, and the holds' rows must keep their say over the biases (the real Xsens session:
  // whitened to unit variance, the turns took the biases to 5700 deg/h). Each group's noise level is estimated at
  // the solution, so the covariance does not depend on this scale.
  return std::sqrt(c.diagonal().mean()) * l.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(2 * t, 2 * t));
}

// The noise's variance of a turn's tangent-plane residual, per axis (half the 2 x 2 block's trace).
double noise_variance(const GravityTurn& g) {
  const auto b = tangent_basis(g.after);
  return 0.5 * (b.transpose() * turn_noise_covariance(g) * b).trace();
}

// R of a turn from outputs less `bias` (identity M): the weights' geometry.
Eigen::Matrix3d raw_rotation(const TriadData& d, const GravityTurn& turn, const Eigen::Vector3d& bias) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  for (std::size_t s = 0; s < turn.samples.size(); ++s) {
    const Eigen::Vector3d angle = (d.gyro.row(turn.samples[s]).transpose() - bias) * turn.dt[s];
    Eigen::Matrix3d step;
    ceres::AngleAxisToRotationMatrix(angle.data(), step.data());
    r = (r * step).eval();
  }
  return r;
}

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
  // Noise of the holds: each hold's direction variance from its accelerometer scatter; the gyro's per-sample
  // variance pooled over the holds (about each hold's mean), and the holds' mean output (the bias, for R's geometry).
  std::vector<double> direction_var;
  double gyro_ss = 0.0, gyro_dof = 0.0;
  Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero();
  double gyro_n = 0.0;
  for (const auto& [begin, end] : holds) {
    const auto b = static_cast<Eigen::Index>(begin), n = static_cast<Eigen::Index>(end - begin);
    const double norm = d.accel.middleRows(b, n).colwise().mean().norm();
    direction_var.push_back(sample_variance(d.accel, begin, end) / (static_cast<double>(n) * norm * norm));
    if (n >= 2) gyro_ss += sample_variance(d.gyro, begin, end) * static_cast<double>(n - 1), gyro_dof += static_cast<double>(n - 1);
    gyro_sum += d.gyro.middleRows(b, n).colwise().sum().transpose();
    gyro_n += static_cast<double>(n);
  }
  const double gyro_var = gyro_dof > 0 ? gyro_ss / gyro_dof : 0.0;
  const Eigen::Vector3d gyro_mean = gyro_sum / std::max(gyro_n, 1.0);
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
    turn.before_var = direction_var[h];
    turn.after_var = direction_var[h + 1];
    double dt2 = 0.0;
    for (double dt : turn.dt) dt2 += dt * dt;
    turn.angle_var = gyro_var * dt2;
    turn.rotation = raw_rotation(d, turn, gyro_mean);
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
                       const TriadLayout& layout, int group, bool whiten) {
  std::vector<int> blocks(layout.misalignment.begin(), layout.misalignment.end());
  blocks.insert(blocks.end(), layout.bias.begin(), layout.bias.end());
  std::vector<GravityTurnCost> costs;
  std::vector<Eigen::Matrix<double, 3, 2>> bases;
  for (const GravityTurn& turn : turns) {
    costs.emplace_back(d, turn, spec.start.bias, spec.bias_order);
    bases.push_back(tangent_basis(turn.after));
  }
  Eigen::MatrixXd whitening = whiten ? turn_whitening(turns, bases) : Eigen::MatrixXd::Identity(2 * static_cast<Eigen::Index>(turns.size()), 2 * static_cast<Eigen::Index>(turns.size()));
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<AllTurnsCost, 4>>(new AllTurnsCost(std::move(costs), std::move(bases), std::move(whitening)));
  for (int b : blocks) cost->AddParameterBlock(p.block(b).size());
  cost->SetNumResiduals(static_cast<int>(2 * turns.size()));
  p.add_residual(std::move(cost), blocks, group);
}

double turn_misfit_variance(const TriadData& d, const std::vector<GravityTurn>& turns, const TriadModel& model, int bias_order) {
  std::vector<std::vector<double>> blocks;
  for (int i = 0; i < 3; ++i) blocks.push_back({model.misalignment(i, 0), model.misalignment(i, 1), model.misalignment(i, 2)});
  for (int i = 0; i < 3; ++i) {
    const Eigen::VectorXd& c = model.bias.coefficients[static_cast<std::size_t>(i)];
    std::vector<double> b(static_cast<std::size_t>(bias_order + 1), 0.0);
    for (Eigen::Index o = 0; o < c.size() && o <= bias_order; ++o) b[static_cast<std::size_t>(o)] = c(o);
    blocks.push_back(b);
  }
  std::vector<const double*> p;
  for (const auto& b : blocks) p.push_back(b.data());
  double residual2 = 0.0, noise = 0.0;
  for (const GravityTurn& turn : turns) {
    double r[3];
    GravityTurnCost(d, turn, model.bias, bias_order)(p.data(), r);
    residual2 += (tangent_basis(turn.after).transpose() * Eigen::Vector3d(r[0], r[1], r[2])).squaredNorm();
    noise += noise_variance(turn);
  }
  const double n = static_cast<double>(std::max<std::size_t>(turns.size(), 1));
  return std::max(0.0, residual2 / (2.0 * n) - noise / n);
}

}  // namespace gyrosid
