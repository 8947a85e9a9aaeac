#include "solvers/nls/nls_covariance.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>
#include <glog/logging.h>

#include <Eigen/QR>

#include <cmath>
#include <memory>
#include <set>

#include "core/error.h"
#include "solvers/nls/nls_scaling.h"

namespace gyrosid {
namespace {

// The free entries (indices into free_entries()) that the residual blocks of `group` depend on, ascending.
std::vector<int> touched_entries(const NlsProblem& p, int group) {
  std::set<int> blocks;
  for (const auto& r : p.residual_blocks()) {
    if (r.group == group) blocks.insert(r.blocks.begin(), r.blocks.end());
  }
  std::vector<int> out;
  const auto& free = p.free_entries();
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (blocks.count(free[j].block)) out.push_back(static_cast<int>(j));
  }
  return out;
}

Eigen::MatrixXd columns_of(const Eigen::MatrixXd& jac, const std::vector<int>& cols) {
  Eigen::MatrixXd out(jac.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c) out.col(static_cast<Eigen::Index>(c)) = jac.col(cols[c]);
  return out;
}

// A residual block scaled by a constant (the group's 1/s_g) for the covariance.
class WeightedCost : public ceres::CostFunction {
 public:
  WeightedCost(const ceres::CostFunction* inner, double weight) : inner_(inner), weight_(weight) {
    set_num_residuals(inner->num_residuals());
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    if (!inner_->Evaluate(p, r, j)) return false;
    const int n = num_residuals();
    for (int i = 0; i < n; ++i) r[i] *= weight_;
    if (j) {
      const auto& sizes = parameter_block_sizes();
      for (std::size_t b = 0; b < sizes.size(); ++b) {
        if (!j[b]) continue;
        for (int k = 0; k < n * sizes[b]; ++k) j[b][k] *= weight_;
      }
    }
    return true;
  }

 private:
  const ceres::CostFunction* inner_;
  double weight_;
};

std::unique_ptr<ceres::Covariance> compute_covariance(ceres::Problem& problem, const std::vector<const double*>& blocks,
                                                     ceres::CovarianceAlgorithmType algorithm) {
  ceres::Covariance::Options o;
  o.algorithm_type = algorithm;
  o.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  o.num_threads = 1;
  // Dense SVD (the fallback) drops directions below the condition limit: a pseudo-inverse over what the
  // data determine, e.g. RBF nodes that ended up without support; sparse QR needs full rank.
  o.null_space_rank = algorithm == ceres::DENSE_SVD ? -1 : 0;
  o.min_reciprocal_condition_number = 1e-14;
  std::vector<std::pair<const double*, const double*>> pairs;
  for (std::size_t a = 0; a < blocks.size(); ++a)
    for (std::size_t b = a; b < blocks.size(); ++b) pairs.emplace_back(blocks[a], blocks[b]);
  auto out = std::make_unique<ceres::Covariance>(o);
  // A rank-deficient sparse attempt is expected (the dense fallback handles it): keep glog quiet meanwhile.
  const int level = FLAGS_minloglevel;
  FLAGS_minloglevel = google::GLOG_FATAL;
  const bool ok = out->Compute(pairs, &problem);
  FLAGS_minloglevel = level;
  return ok ? std::move(out) : nullptr;
}

// A weighted copy of the problem at its stored values, for ceres::Covariance: each residual group scaled by
// 1/sigma, constant blocks and manifolds as in the problem. Ceres orders the covariance's columns by the
// blocks' addresses (it sorts them: internal/ceres/covariance_impl.cc), so the copy's blocks live in one
// buffer, in block order; in their own allocations the round-off of every sigma would follow the heap's
// layout, and an unrelated change of the program would move their last digits.
struct WeightedCopy {
  std::vector<double> values;  // every block's stored values, one block after the other
  ceres::Problem base;         // the problem as solved: its constant blocks and manifolds (owned here)
  std::unique_ptr<ceres::Problem> weighted;
  std::vector<const double*> blocks;  // the free blocks in `weighted`, in block order
  std::vector<int> block_ids;         // ... and their indices in the problem

  WeightedCopy(const NlsProblem& p, const std::vector<double>& group_sigma)
      : base(ceres_problem(const_cast<NlsProblem&>(p))) {  // points Ceres at the stored values; nothing is changed
    std::vector<std::size_t> offset{0};
    for (int i = 0; i < p.block_count(); ++i) {
      const std::vector<double>& v = p.block(i).values;
      values.insert(values.end(), v.begin(), v.end());
      offset.push_back(values.size());
    }
    const auto at = [&](int i) { return values.data() + offset[static_cast<std::size_t>(i)]; };
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    weighted = std::make_unique<ceres::Problem>(po);
    for (const auto& rb : p.residual_blocks()) {
      const double s = group_sigma[static_cast<std::size_t>(rb.group)];
      std::vector<double*> parameters;
      for (int bi : rb.blocks) parameters.push_back(at(bi));
      weighted->AddResidualBlock(new WeightedCost(rb.cost.get(), s > 0 ? 1.0 / s : 1.0), nullptr, parameters);
    }
    for (int i = 0; i < p.block_count(); ++i) {
      double* data = at(i);
      double* stored = const_cast<double*>(p.block(i).values.data());
      if (!weighted->HasParameterBlock(data)) continue;
      if (base.HasParameterBlock(stored) && base.IsParameterBlockConstant(stored)) {
        weighted->SetParameterBlockConstant(data);
        continue;
      }
      if (base.HasParameterBlock(stored) && base.GetManifold(stored)) weighted->SetManifold(data, const_cast<ceres::Manifold*>(base.GetManifold(stored)));
      blocks.push_back(data);
      block_ids.push_back(i);
    }
  }
};

}  // namespace

namespace {
// v less its projection on an orthonormal basis (twice: modified Gram-Schmidt with reorthogonalisation).
Eigen::VectorXd project_out(Eigen::VectorXd v, const std::vector<Eigen::VectorXd>& basis) {
  for (int pass = 0; pass < 2; ++pass)
    for (const auto& q : basis) v -= q.dot(v) * q;
  return v;
}
}  // namespace

NlsObservability analyse_observability(const NlsProblem& p, const std::vector<double>& tolerance, const std::vector<bool>& anchor) {
  const auto n = p.free_entries().size();
  NlsObservability out;
  out.observable.assign(n, false);
  for (int g = 0; g < p.groups(); ++g) {
    const std::vector<int> cols = touched_entries(p, g);
    Eigen::VectorXd r;
    Eigen::MatrixXd jac;
    p.linearize(g, r, jac);
    const Eigen::MatrixXd j = columns_of(jac, cols);
    // R of the scaled Jacobian: QR is orthogonally invariant, so scale R's columns rather than J's.
    Eigen::MatrixXd rf;
    if (j.rows() >= j.cols()) {
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(j);
      rf = qr.matrixQR().topRows(j.cols()).triangularView<Eigen::Upper>();
    } else {
      rf = j;
    }
    std::vector<Eigen::VectorXd> basis, anchors;
    for (Eigen::Index c = 0; c < rf.cols(); ++c) {
      const double norm = rf.col(c).norm();
      if (!(norm > 0) || !std::isfinite(norm)) continue;
      const auto entry = static_cast<std::size_t>(cols[static_cast<std::size_t>(c)]);
      const Eigen::VectorXd unit = rf.col(c) / norm;
      const Eigen::VectorXd v = project_out(unit, basis);
      const double rest = v.norm();
      if (rest < 1e-7) continue;
      const bool is_anchor = !anchor.empty() && anchor.at(entry);
      if (!anchor.empty() && !is_anchor && !tolerance.empty() && project_out(unit, anchors).norm() < tolerance.at(entry)) continue;
      basis.push_back(v / rest);
      if (is_anchor) anchors.push_back(project_out(unit, anchors).normalized());
      out.observable[entry] = true;
    }
    out.rank.push_back(static_cast<int>(basis.size()));
    out.columns.push_back(static_cast<int>(cols.size()));
  }
  return out;
}

NlsCovariance estimate_covariance(const NlsProblem& p) {
  NlsCovariance out;
  const auto& free = p.free_entries();
  const auto n = static_cast<Eigen::Index>(free.size());
  // Noise level of each group from its residuals at the solution.
  out.group_sigma.assign(static_cast<std::size_t>(p.groups()), 0.0);
  out.group_dof.assign(static_cast<std::size_t>(p.groups()), 0);
  Eigen::VectorXd column_norm2 = Eigen::VectorXd::Zero(n);
  for (int g = 0; g < p.groups(); ++g) {
    Eigen::VectorXd r;
    Eigen::MatrixXd jac;
    p.linearize(g, r, jac);
    const int dof = static_cast<int>(r.size()) - static_cast<int>(touched_entries(p, g).size());
    out.group_dof[static_cast<std::size_t>(g)] = dof;
    if (dof <= 0) {
      out.message = str_cat("residual group ", g, " has ", r.size(), " residuals for ", touched_entries(p, g).size(), " free parameters: no degrees of freedom to estimate its noise");
      return out;
    }
    const double s = std::sqrt(r.squaredNorm() / dof);
    out.group_sigma[static_cast<std::size_t>(g)] = s;
    if (s > 0) column_norm2 += jac.colwise().squaredNorm().transpose() / (s * s);
  }
  WeightedCopy copy(p, out.group_sigma);
  const std::vector<const double*>& blocks = copy.blocks;
  const std::vector<int>& block_ids = copy.block_ids;
  ceres::Problem& weighted = *copy.weighted;
  std::unique_ptr<ceres::Covariance> cov = compute_covariance(weighted, blocks, ceres::SPARSE_QR);
  if (!cov) cov = compute_covariance(weighted, blocks, ceres::DENSE_SVD);
  if (!cov) {
    out.message = "ceres::Covariance failed: the free parameters are not all determined by the data";
    return out;
  }
  // Assemble free x free from the block covariances (fixed entries of a block are dropped).
  std::vector<std::vector<int>> free_of_block(static_cast<std::size_t>(p.block_count()));
  for (std::size_t j = 0; j < free.size(); ++j) free_of_block[static_cast<std::size_t>(free[j].block)].push_back(static_cast<int>(j));
  out.covariance = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t a = 0; a < blocks.size(); ++a) {
    for (std::size_t b = a; b < blocks.size(); ++b) {
      const int ba = block_ids[a], bb = block_ids[b];
      const int sa = p.block(ba).size(), sb = p.block(bb).size();
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(sa, sb);
      cov->GetCovarianceBlock(blocks[a], blocks[b], c.data());
      for (int fa : free_of_block[static_cast<std::size_t>(ba)]) {
        for (int fb : free_of_block[static_cast<std::size_t>(bb)]) {
          const double v = c(free[static_cast<std::size_t>(fa)].entry, free[static_cast<std::size_t>(fb)].entry);
          out.covariance(fa, fb) = v;
          out.covariance(fb, fa) = v;
        }
      }
    }
  }
  out.sigma = out.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.inflation = out.sigma.cwiseProduct(column_norm2.cwiseSqrt());
  out.ok = true;
  return out;
}

}  // namespace gyrosid
