#include "solvers/triad/triad_problem.h"

#include <ceres/cost_function.h>

#include <cmath>

#include "core/error.h"
#include "core/triad_axes.h"
#include "model/gaussian_node.h"

namespace gyrosid {
namespace {

constexpr int kRowsPerBlock = 256;

// Rows [begin, end) of one gyro: r = A theta_linear + sum_nodes - y (linear blocks in A's column order,
// then the node blocks).
class TriadRowsCost : public ceres::CostFunction {
 public:
  TriadRowsCost(Eigen::MatrixXd a, Eigen::VectorXd y, const std::vector<int>& linear_sizes, const SurfaceTerm* term,
                std::vector<int> start, Eigen::MatrixXd inputs, std::vector<double> weights)
      : a_(std::move(a)), y_(std::move(y)), linear_blocks_(static_cast<int>(linear_sizes.size())), term_(term),
        start_(std::move(start)), inputs_(std::move(inputs)), weights_(std::move(weights)) {
    set_num_residuals(static_cast<int>(y_.size()));
    for (int s : linear_sizes) mutable_parameter_block_sizes()->push_back(s);
    for (int j = 0; term_ && j < term_->nodes(); ++j) mutable_parameter_block_sizes()->push_back(term_->node_size());
  }

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const Eigen::Index n = y_.size();
    Eigen::Map<Eigen::VectorXd> r(residuals, n);
    r = -y_;
    Eigen::Index col = 0;
    const auto& sizes = parameter_block_sizes();
    for (int b = 0; b < linear_blocks_; ++b) {
      const int size = sizes[static_cast<std::size_t>(b)];
      r.noalias() += a_.middleCols(col, size) * Eigen::Map<const Eigen::VectorXd>(p[b], size);
      if (jacobians && jacobians[b]) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[b], n, size) = a_.middleCols(col, size);
      }
      col += size;
    }
    if (!term_ || term_->nodes() == 0) return true;
    const int nodes = term_->nodes(), size = term_->node_size();
    for (int j = 0; j < nodes; ++j) {
      double* jac = jacobians ? jacobians[node_block(j)] : nullptr;
      if (jac) std::fill(jac, jac + n * size, 0.0);
    }
    std::vector<double> grad(static_cast<std::size_t>(size));
    for (Eigen::Index row = 0; row < n; ++row) {
      for (int e = start_[static_cast<std::size_t>(row)]; e < start_[static_cast<std::size_t>(row) + 1]; ++e) {
        const double w = weights_[static_cast<std::size_t>(e)];
        const double* x = inputs_.row(e).data();
        for (int j = 0; j < nodes; ++j) {
          double* jac = jacobians ? jacobians[node_block(j)] : nullptr;
          r(row) += w * term_->node_output(x, p[node_block(j)], jac ? grad.data() : nullptr);
          if (jac)
            for (int c = 0; c < size; ++c) jac[row * size + c] += w * grad[static_cast<std::size_t>(c)];
        }
      }
    }
    return true;
  }

 private:
  int node_block(int j) const { return linear_blocks_ + j; }  // the blocks: the linear ones, then a node's each

  Eigen::MatrixXd a_;
  Eigen::VectorXd y_;
  int linear_blocks_;
  const SurfaceTerm* term_;
  std::vector<int> start_;  // per row, into inputs_/weights_ (local, relative)
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> inputs_;
  std::vector<double> weights_;
};

// The surface's weight penalty: r = P w - t, w_j the weight of node block j (a NodeBlock); linear in w.
class WeightPenaltyCost : public ceres::CostFunction {
 public:
  WeightPenaltyCost(Eigen::MatrixXd p, Eigen::VectorXd t, int node_size)
      : p_(std::move(p)), t_(std::move(t)), node_size_(node_size), dim_(NodeBlock<double>::dimension_of(node_size)) {
    set_num_residuals(static_cast<int>(p_.rows()));
    for (Eigen::Index j = 0; j < p_.cols(); ++j) mutable_parameter_block_sizes()->push_back(node_size);
  }
  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    const Eigen::Index k = p_.cols();
    Eigen::VectorXd w(k);
    for (Eigen::Index j = 0; j < k; ++j) w(j) = NodeBlock<const double>{blocks[j], dim_}.weight();
    Eigen::Map<Eigen::VectorXd>(residuals, p_.rows()) = p_ * w - t_;
    for (Eigen::Index j = 0; jacobians && j < k; ++j) {
      if (!jacobians[j]) continue;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(jacobians[j], p_.rows(), node_size_);
      jac.setZero();
      jac.col(NodeBlock<double>::weight_index(dim_)) = p_.col(j);
    }
    return true;
  }

 private:
  Eigen::MatrixXd p_;
  Eigen::VectorXd t_;
  int node_size_;
  Eigen::Index dim_;
};

std::vector<std::string> names(const std::string& prefix, const std::vector<std::string>& entries) {
  std::vector<std::string> out;
  for (const auto& e : entries) out.push_back(prefix + e);
  return out;
}

std::vector<double> row_of(const Eigen::Matrix3d& m, int i) { return {m(i, 0), m(i, 1), m(i, 2)}; }

// The linear design row of one sample of gyro `axis`: omega | v^0..v^nb | f | surface columns.
void design_row(const TriadData& d, int axis, Eigen::Index k, const TriadProblemSpec& spec, double* out) {
  int c = 0;
  for (int j = 0; j < 3; ++j) out[c++] = d.reference(k, j);
  const double v = spec.start.bias.normalised(d.temp_c(k, axis));
  double vp = 1.0;
  for (int o = 0; o <= spec.bias_order; ++o, vp *= v) out[c++] = vp;
  if (spec.g_sensitivity)
    for (int j = 0; j < 3; ++j) out[c++] = d.accel(k, j);
  if (const SurfaceTerm* s = spec.surfaces[static_cast<std::size_t>(axis)]) s->linear_columns(spec.surface_rate_at(d, k, axis), d.temp_c(k, axis), out + c);
}

}  // namespace

TriadRows rate_rows(const TriadData& d) {
  TriadRows rows;
  for (Eigen::Index k = 0; k < d.size(); ++k) rows.add_sample(static_cast<int>(k));
  rows.description = str_cat(d.size(), " samples against the recorded reference rates");
  return rows;
}

TriadRows angle_rows(const TriadData& d) {
  if (d.position_id.empty()) {
    fail("triad: the angle reference integrates each segment of constant position_id; the recording has no position_id column");
  }
  TriadRows rows;
  const auto n = static_cast<std::size_t>(d.size());
  int integrated = 0, held = 0;
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin;
    while (end < n && d.position_id[end] == d.position_id[begin]) ++end;
    if (d.reference.middleRows(static_cast<Eigen::Index>(begin), static_cast<Eigen::Index>(end - begin)).isZero(0.0)) {
      // A static hold (reference 0 throughout): known at every sample, one row each.
      for (std::size_t k = begin; k < end; ++k) rows.add_sample(static_cast<int>(k));
      ++held;
    } else {
      // A turn known by its angle: one row, the integral over the segment. Sample k is the mean rate over
      // (t_{k-1}, t_k]; the first sample of a segment takes the following interval. Weights dt_k / sqrt(sum dt^2)
      // give the row the noise of one sample, like the per-sample rows.
      std::vector<double> dt;
      double sum2 = 0.0;
      for (std::size_t k = begin; k < end; ++k) {
        const double h = k > begin ? d.t_s[k] - d.t_s[k - 1] : (end - begin > 1 ? d.t_s[k + 1] - d.t_s[k] : 1.0);
        dt.push_back(h);
        sum2 += h * h;
      }
      for (std::size_t k = begin; k < end; ++k) {
        rows.sample.push_back(static_cast<int>(k));
        rows.weight.push_back(dt[k - begin] / std::sqrt(sum2));
      }
      rows.start.push_back(static_cast<int>(rows.sample.size()));
      ++integrated;
    }
    begin = end;
  }
  rows.description = str_cat(integrated, " turns known by their integral (known angles) and ", held,
                             " static holds sample by sample, segments of constant position_id");
  return rows;
}

NlsProblem build_triad_problem(const TriadData& d, const TriadRows& rows, const TriadProblemSpec& spec, TriadLayout& layout) {
  if (!d.has_reference()) fail("triad: the recording's ref_rate_{x,y,z}_dps must be finite everywhere");
  if (spec.g_sensitivity && !d.has_accel()) fail("triad: g-sensitivity needs the accel_{x,y,z}_mps2 columns");
  if (spec.g_sensitivity && !d.accel.allFinite()) fail("triad: g-sensitivity needs accel_{x,y,z}_mps2 at every sample (found nan)");
  NlsProblem p;
  layout = TriadLayout{};
  for (int i = 0; i < 3; ++i) {
    const auto ai = static_cast<std::size_t>(i);
    const std::string ax = kTriadAxes[i];
    layout.misalignment[ai] = p.add_block("misalignment_" + ax, row_of(spec.start.misalignment, i),
                                          {"M_" + ax + "x", "M_" + ax + "y", "M_" + ax + "z"});
    std::vector<double> b(static_cast<std::size_t>(spec.bias_order + 1), 0.0);
    std::vector<std::string> bn;
    const Eigen::VectorXd& b0 = spec.start.bias.coefficients[ai];
    for (int o = 0; o <= spec.bias_order; ++o) {
      if (o < b0.size()) b[static_cast<std::size_t>(o)] = b0(o);
      bn.push_back(str_cat("bias_", ax, "_c", o));
    }
    layout.bias[ai] = p.add_block("bias_" + ax, b, bn);
    std::vector<int> linear = {layout.misalignment[ai], layout.bias[ai]};
    if (spec.g_sensitivity) {
      const Eigen::Matrix3d g = spec.start.g_sensitivity.value_or(Eigen::Matrix3d::Zero());
      layout.g_sensitivity[ai] = p.add_block("g_sensitivity_" + ax, row_of(g, i), {"G_" + ax + "x", "G_" + ax + "y", "G_" + ax + "z"});
      linear.push_back(layout.g_sensitivity[ai]);
    }
    const SurfaceTerm* term = spec.surfaces[ai];
    if (term && term->linear_size() > 0) {
      layout.surface[ai] = p.add_block("surface_" + ax, term->linear_start(), names("surface_" + ax + "_", term->linear_names()));
      linear.push_back(layout.surface[ai]);
    }
    std::vector<int> blocks = linear;
    for (int j = 0; term && j < term->nodes(); ++j) {
      const int nb = p.add_block(str_cat("surface_", ax, "_node", j), term->node_start(j));
      layout.nodes[ai].push_back(nb);
      blocks.push_back(nb);
    }
    std::vector<int> linear_sizes;
    int width = 0;
    for (int b : linear) linear_sizes.push_back(p.block(b).size()), width += p.block(b).size();

    // Residual blocks of kRowsPerBlock rows each.
    std::vector<double> design(static_cast<std::size_t>(width));
    const int inputs = term ? term->input_size() : 0;
    for (int r0 = 0; r0 < rows.rows(); r0 += kRowsPerBlock) {
      const int r1 = std::min(rows.rows(), r0 + kRowsPerBlock);
      Eigen::MatrixXd a = Eigen::MatrixXd::Zero(r1 - r0, width);
      Eigen::VectorXd y = Eigen::VectorXd::Zero(r1 - r0);
      const int e0 = rows.start[static_cast<std::size_t>(r0)], e1 = rows.start[static_cast<std::size_t>(r1)];
      std::vector<int> start;
      Eigen::MatrixXd x(term && term->nodes() > 0 ? e1 - e0 : 0, inputs);
      std::vector<double> w;
      for (int r = r0; r < r1; ++r) {
        start.push_back(rows.start[static_cast<std::size_t>(r)] - e0);
        for (int e = rows.start[static_cast<std::size_t>(r)]; e < rows.start[static_cast<std::size_t>(r) + 1]; ++e) {
          const Eigen::Index k = rows.sample[static_cast<std::size_t>(e)];
          const double we = rows.weight[static_cast<std::size_t>(e)];
          design_row(d, i, k, spec, design.data());
          a.row(r - r0) += we * Eigen::Map<const Eigen::RowVectorXd>(design.data(), width);
          y(r - r0) += we * (d.gyro(k, i) - d.reference(k, i));
          if (x.rows() > 0) {
            Eigen::RowVectorXd xi(inputs);
            term->inputs(spec.surface_rate_at(d, k, i), d.temp_c(k, i), xi.data());
            x.row(e - e0) = xi;
          }
          w.push_back(we);
        }
      }
      start.push_back(e1 - e0);
      p.add_residual(std::make_unique<TriadRowsCost>(std::move(a), std::move(y), linear_sizes, term, std::move(start), std::move(x), std::move(w)),
                     blocks, i);
    }
    if (term && term->weight_penalty().size() > 0) {  // in gyro i's group: it regularises that gyro's rows
      p.add_residual(std::make_unique<WeightPenaltyCost>(term->weight_penalty(), term->weight_target(), term->node_size()), layout.nodes[ai], i);
    }
  }
  return p;
}

TriadModel triad_model_of(const NlsProblem& p, const TriadLayout& layout, const TriadProblemSpec& spec) {
  TriadModel m;
  m.bias.reference_c = spec.start.bias.reference_c;
  m.bias.scale_c = spec.start.bias.scale_c;
  if (spec.g_sensitivity) m.g_sensitivity = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const auto ai = static_cast<std::size_t>(i);
    const auto& row = p.block(layout.misalignment[ai]).values;
    for (int j = 0; j < 3; ++j) m.misalignment(i, j) = row[static_cast<std::size_t>(j)];
    const auto& b = p.block(layout.bias[ai]).values;
    m.bias.coefficients[ai] = Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size()));
    if (spec.g_sensitivity) {
      const auto& g = p.block(layout.g_sensitivity[ai]).values;
      for (int j = 0; j < 3; ++j) (*m.g_sensitivity)(i, j) = g[static_cast<std::size_t>(j)];
    }
    if (const SurfaceTerm* term = spec.surfaces[ai]) {
      std::vector<double> linear;
      if (layout.surface[ai] >= 0) linear = p.block(layout.surface[ai]).values;
      std::vector<std::vector<double>> nodes;
      for (int nb : layout.nodes[ai]) nodes.push_back(p.block(nb).values);
      m.surfaces[ai] = term->model(linear, nodes);
    }
  }
  return m;
}

}  // namespace gyrosid
