// A nonlinear least-squares problem, posed once and solved by any back-end (solvers/nls/nls_solver.h):
//
//   min_x  F(x) = 1/2 sum_b |r_b(x_b)|^2
//
// in Ceres's vocabulary: named parameter blocks (with optional bounds and entries held fixed) and residual
// blocks, each a ceres::CostFunction over some of the blocks with analytic or automatic derivatives
// (ceres::AutoDiffCostFunction). The Ceres back-end hands the blocks to a ceres::Problem as they are; NLopt
// and Ipopt see F, its gradient J'r and the Gauss-Newton matrix J'J through evaluate(), over the free
// entries only. Each residual block belongs to a group (one gyro axis, one sensor) whose noise level the
// covariance estimates separately (nls_covariance.h).
//
//   NlsProblem p;
//   const int m = p.add_block("misalignment_x", {0, 0, 0});
//   p.add_residual(std::make_unique<MyCost>(...), {m}, /*group=*/0);
//   SolveSummary s = solve_nls("ceres", {}, p);   // p's blocks hold the solution afterwards
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace gyrosid {

class NlsProblem {
 public:
  struct ParameterBlock {
    std::string name;
    std::vector<double> values;        // the start on entry to a solve, the solution after it
    std::vector<double> lower, upper;  // empty: unbounded
    std::vector<bool> fixed;           // per entry: held at its value
    std::vector<std::string> entry_names;  // optional labels for reports ("M_xy"); default name[i]
    int size() const { return static_cast<int>(values.size()); }
  };
  struct ResidualBlock {
    std::unique_ptr<ceres::CostFunction> cost;
    std::vector<int> blocks;  // parameter block indices, in the cost function's order
    int group = 0;
  };

  int add_block(std::string name, std::vector<double> values, std::vector<std::string> entry_names = {});
  void set_bounds(int block, std::vector<double> lower, std::vector<double> upper);
  void fix(int block, int entry, bool fixed = true);
  void add_residual(std::unique_ptr<ceres::CostFunction> cost, std::vector<int> blocks, int group = 0);

  int block_count() const { return static_cast<int>(blocks_.size()); }
  ParameterBlock& block(int i) { return blocks_.at(static_cast<std::size_t>(i)); }
  const ParameterBlock& block(int i) const { return blocks_.at(static_cast<std::size_t>(i)); }
  int find_block(const std::string& name) const;  // -1 when absent
  const std::vector<ResidualBlock>& residual_blocks() const { return residuals_; }
  int groups() const { return groups_; }
  int residual_count(int group = -1) const;  // of one group, or all (-1)
  std::string entry_name(int block, int entry) const;

  // The free (not fixed) entries, packed block after block: their count, values, bounds and labels.
  struct FreeEntry {
    int block, entry;
  };
  const std::vector<FreeEntry>& free_entries() const;
  Eigen::VectorXd free_values() const;
  void set_free_values(const Eigen::VectorXd& x);
  bool bounded() const;
  Eigen::VectorXd free_lower() const;  // -inf where unbounded
  Eigen::VectorXd free_upper() const;

  // F at the free values x (the fixed entries as stored), with the gradient J'r and the Gauss-Newton matrix
  // J'J (dense, free x free) when asked. Residual blocks are evaluated one at a time; no dense J is formed.
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient = nullptr, Eigen::MatrixXd* gauss_newton = nullptr) const;
  // Residuals and the dense Jacobian (rows: the group's residuals; columns: free entries) at the stored
  // values, for one group - what the covariance and observability analyses factorise.
  void linearize(int group, Eigen::VectorXd& residuals, Eigen::MatrixXd& jacobian) const;

 private:
  // One residual block's Jacobian over the free entries it touches: columns[c] is the free index of
  // jacobian column c.
  struct LocalJacobian {
    Eigen::MatrixXd jacobian;
    std::vector<int> columns;
  };
  // Evaluates one residual block at the stored values overridden by `x` (free entries); fills the block's
  // residuals and, when `local` is not null, its Jacobian over the free entries it touches.
  bool evaluate_block(const ResidualBlock& r, const Eigen::VectorXd& x, double* residuals, LocalJacobian* local) const;
  void invalidate() { free_dirty_ = true; }

  std::vector<ParameterBlock> blocks_;
  std::vector<ResidualBlock> residuals_;
  int groups_ = 0;
  mutable std::vector<FreeEntry> free_;
  mutable std::vector<std::vector<int>> free_index_;  // [block][entry] -> free index or -1
  mutable bool free_dirty_ = true;
};

}  // namespace gyrosid
