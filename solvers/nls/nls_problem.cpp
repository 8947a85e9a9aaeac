#include "solvers/nls/nls_problem.h"

#include <limits>

#include "core/error.h"

namespace gyrosid {

int NlsProblem::add_block(std::string name, std::vector<double> values, std::vector<std::string> entry_names) {
  if (find_block(name) >= 0) fail("nls problem: parameter block '", name, "' added twice");
  if (!entry_names.empty() && entry_names.size() != values.size()) fail("nls problem: block '", name, "' has ", values.size(), " entries but ", entry_names.size(), " names");
  ParameterBlock b;
  b.name = std::move(name);
  b.fixed.assign(values.size(), false);
  b.values = std::move(values);
  b.entry_names = std::move(entry_names);
  blocks_.push_back(std::move(b));
  invalidate();
  return block_count() - 1;
}

void NlsProblem::set_bounds(int i, std::vector<double> lower, std::vector<double> upper) {
  ParameterBlock& b = block(i);
  if (lower.size() != b.values.size() || upper.size() != b.values.size()) fail("nls problem: bounds of '", b.name, "' have the wrong size");
  for (std::size_t k = 0; k < lower.size(); ++k) {
    if (!(lower[k] <= upper[k])) fail("nls problem: bounds of '", entry_name(i, static_cast<int>(k)), "' are empty");
  }
  b.lower = std::move(lower);
  b.upper = std::move(upper);
}

void NlsProblem::fix(int i, int entry, bool fixed) {
  block(i).fixed.at(static_cast<std::size_t>(entry)) = fixed;
  invalidate();
}

void NlsProblem::add_residual(std::unique_ptr<ceres::CostFunction> cost, std::vector<int> blocks, int group) {
  const auto& sizes = cost->parameter_block_sizes();
  if (sizes.size() != blocks.size()) fail("nls problem: a cost function over ", sizes.size(), " blocks was given ", blocks.size());
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    if (block(blocks[k]).size() != sizes[k]) {
      fail("nls problem: block '", block(blocks[k]).name, "' has ", block(blocks[k]).size(), " entries, the cost expects ", sizes[k]);
    }
  }
  if (group < 0) fail("nls problem: negative residual group");
  groups_ = std::max(groups_, group + 1);
  residuals_.push_back({std::move(cost), std::move(blocks), group});
}

int NlsProblem::find_block(const std::string& name) const {
  for (int i = 0; i < block_count(); ++i) {
    if (blocks_[static_cast<std::size_t>(i)].name == name) return i;
  }
  return -1;
}

int NlsProblem::residual_count(int group) const {
  int n = 0;
  for (const auto& r : residuals_) {
    if (group < 0 || r.group == group) n += r.cost->num_residuals();
  }
  return n;
}

std::string NlsProblem::entry_name(int i, int entry) const {
  const ParameterBlock& b = block(i);
  if (!b.entry_names.empty()) return b.entry_names.at(static_cast<std::size_t>(entry));
  return str_cat(b.name, "[", entry, "]");
}

const std::vector<NlsProblem::FreeEntry>& NlsProblem::free_entries() const {
  if (free_dirty_) {
    free_.clear();
    free_index_.assign(blocks_.size(), {});
    for (int i = 0; i < block_count(); ++i) {
      const ParameterBlock& b = blocks_[static_cast<std::size_t>(i)];
      free_index_[static_cast<std::size_t>(i)].assign(b.values.size(), -1);
      for (int k = 0; k < b.size(); ++k) {
        if (b.fixed[static_cast<std::size_t>(k)]) continue;
        free_index_[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = static_cast<int>(free_.size());
        free_.push_back({i, k});
      }
    }
    free_dirty_ = false;
  }
  return free_;
}

Eigen::VectorXd NlsProblem::free_values() const {
  const auto& f = free_entries();
  Eigen::VectorXd x(static_cast<Eigen::Index>(f.size()));
  for (std::size_t j = 0; j < f.size(); ++j) x(static_cast<Eigen::Index>(j)) = block(f[j].block).values[static_cast<std::size_t>(f[j].entry)];
  return x;
}

void NlsProblem::set_free_values(const Eigen::VectorXd& x) {
  const auto& f = free_entries();
  for (std::size_t j = 0; j < f.size(); ++j) block(f[j].block).values[static_cast<std::size_t>(f[j].entry)] = x(static_cast<Eigen::Index>(j));
}

bool NlsProblem::bounded() const {
  for (const auto& b : blocks_) {
    if (!b.lower.empty()) return true;
  }
  return false;
}

Eigen::VectorXd NlsProblem::free_lower() const {
  const auto& f = free_entries();
  Eigen::VectorXd v(static_cast<Eigen::Index>(f.size()));
  for (std::size_t j = 0; j < f.size(); ++j) {
    const ParameterBlock& b = block(f[j].block);
    v(static_cast<Eigen::Index>(j)) = b.lower.empty() ? -std::numeric_limits<double>::infinity() : b.lower[static_cast<std::size_t>(f[j].entry)];
  }
  return v;
}

Eigen::VectorXd NlsProblem::free_upper() const {
  const auto& f = free_entries();
  Eigen::VectorXd v(static_cast<Eigen::Index>(f.size()));
  for (std::size_t j = 0; j < f.size(); ++j) {
    const ParameterBlock& b = block(f[j].block);
    v(static_cast<Eigen::Index>(j)) = b.upper.empty() ? std::numeric_limits<double>::infinity() : b.upper[static_cast<std::size_t>(f[j].entry)];
  }
  return v;
}

bool NlsProblem::evaluate_block(const ResidualBlock& r, const Eigen::VectorXd& x, double* residuals,
                                LocalJacobian* local) const {
  free_entries();
  const std::size_t nb = r.blocks.size();
  std::vector<std::vector<double>> values(nb);
  std::vector<const double*> params(nb);
  std::vector<std::vector<double>> block_jac(local ? nb : 0);
  std::vector<double*> jac_ptrs(nb, nullptr);
  const int nr = r.cost->num_residuals();
  for (std::size_t k = 0; k < nb; ++k) {
    const int bi = r.blocks[k];
    values[k] = block(bi).values;
    const auto& index = free_index_[static_cast<std::size_t>(bi)];
    for (std::size_t e = 0; e < values[k].size(); ++e) {
      if (index[e] >= 0) values[k][e] = x(index[e]);
    }
    params[k] = values[k].data();
    if (local) {
      block_jac[k].assign(static_cast<std::size_t>(nr) * values[k].size(), 0.0);
      jac_ptrs[k] = block_jac[k].data();
    }
  }
  if (!r.cost->Evaluate(params.data(), residuals, local ? jac_ptrs.data() : nullptr)) return false;
  if (!local) return true;
  // Columns of the free entries this block touches (a block may appear once only in a cost's list).
  local->columns.clear();
  for (std::size_t k = 0; k < nb; ++k) {
    for (int idx : free_index_[static_cast<std::size_t>(r.blocks[k])]) {
      if (idx >= 0) local->columns.push_back(idx);
    }
  }
  local->jacobian.resize(nr, static_cast<Eigen::Index>(local->columns.size()));
  Eigen::Index c = 0;
  for (std::size_t k = 0; k < nb; ++k) {
    const auto& index = free_index_[static_cast<std::size_t>(r.blocks[k])];
    const std::size_t size = values[k].size();
    for (std::size_t e = 0; e < size; ++e) {
      if (index[e] < 0) continue;
      for (int i = 0; i < nr; ++i) local->jacobian(i, c) = block_jac[k][static_cast<std::size_t>(i) * size + e];
      ++c;
    }
  }
  return true;
}

double NlsProblem::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient, Eigen::MatrixXd* gauss_newton) const {
  const auto n = static_cast<Eigen::Index>(free_entries().size());
  if (x.size() != n) fail("nls problem: evaluate at ", x.size(), " values, the problem has ", n, " free entries");
  if (gradient) gradient->setZero(n);
  if (gauss_newton) gauss_newton->setZero(n, n);
  const bool derivatives = gradient || gauss_newton;
  double cost = 0.0;
  Eigen::VectorXd res;
  LocalJacobian local;
  for (const auto& r : residuals_) {
    res.resize(r.cost->num_residuals());
    if (!evaluate_block(r, x, res.data(), derivatives ? &local : nullptr)) return std::numeric_limits<double>::infinity();
    cost += 0.5 * res.squaredNorm();
    if (!derivatives) continue;
    const auto m = static_cast<Eigen::Index>(local.columns.size());
    if (gradient) {
      const Eigen::VectorXd g = local.jacobian.transpose() * res;
      for (Eigen::Index a = 0; a < m; ++a) (*gradient)(local.columns[static_cast<std::size_t>(a)]) += g(a);
    }
    if (gauss_newton) {
      const Eigen::MatrixXd h = local.jacobian.transpose() * local.jacobian;
      for (Eigen::Index a = 0; a < m; ++a)
        for (Eigen::Index b = 0; b < m; ++b) (*gauss_newton)(local.columns[static_cast<std::size_t>(a)], local.columns[static_cast<std::size_t>(b)]) += h(a, b);
    }
  }
  return cost;
}

void NlsProblem::linearize(int group, Eigen::VectorXd& residuals, Eigen::MatrixXd& jacobian) const {
  const Eigen::VectorXd x = free_values();
  const Eigen::Index rows = residual_count(group);
  residuals.resize(rows);
  jacobian.setZero(rows, x.size());
  Eigen::Index row = 0;
  LocalJacobian local;
  for (const auto& r : residuals_) {
    if (r.group != group) continue;
    if (!evaluate_block(r, x, residuals.data() + row, &local)) fail("nls problem: a residual block of group ", group, " cannot be evaluated at the solution");
    for (std::size_t a = 0; a < local.columns.size(); ++a) {
      jacobian.block(row, local.columns[a], local.jacobian.rows(), 1) += local.jacobian.col(static_cast<Eigen::Index>(a));
    }
    row += r.cost->num_residuals();
  }
}

}  // namespace gyrosid
