#include "solvers/triad/surface_terms.h"

#include <Eigen/QR>

#include <cmath>

#include "core/error.h"
#include "model/gaussian_node.h"

namespace gyrosid {

void SurfaceTerm::linear_columns(double, double, double*) const {}
std::vector<double> SurfaceTerm::node_start(int) const { return {}; }
void SurfaceTerm::inputs(double, double, double*) const {}
double SurfaceTerm::node_output(const double*, const double*, double*) const { return 0.0; }
const Eigen::MatrixXd& SurfaceTerm::weight_penalty() const {
  static const Eigen::MatrixXd none;
  return none;
}
const Eigen::VectorXd& SurfaceTerm::weight_target() const {
  static const Eigen::VectorXd none;
  return none;
}
std::vector<std::string> SurfaceTerm::linear_names() const {
  std::vector<std::string> out;
  for (int k = 0; k < linear_size(); ++k) out.push_back(str_cat("c", k));
  return out;
}

namespace {

class ClassicalTerm : public SurfaceTerm {
 public:
  ClassicalTerm(const ClassicalOptions& o, const Eigen::VectorXd& rates, const Eigen::VectorXd& temps)
      : options_(o), shape_(default_features(), ModelTarget::error) {
    options_.bias_order = 0;
    shape_.rate_scale = std::max(rates.cwiseAbs().maxCoeff(), 1e-6);
    shape_.temperature_reference = 0.5 * (temps.maxCoeff() + temps.minCoeff());
    shape_.temperature_scale = std::max(0.5 * (temps.maxCoeff() - temps.minCoeff()), 1.0);
    // The term's linear parameters: classical_columns' but the bias group and u^0 w, which belong to the triad
    // (b, M_ii: M_ii carries the whole constant scale factor, against the reference rate).
    const ClassicalColumns g(options_);
    for (Eigen::Index c = g.bias.end(); c < g.size(); ++c) {
      if (c != g.sf_rate.first) columns_.push_back(c);
    }
  }
  int linear_size() const override { return static_cast<int>(columns_.size()); }
  void linear_columns(double rate, double temp_c, double* out) const override {
    const Eigen::MatrixXd c = classical_columns(shape_, options_, Eigen::VectorXd::Constant(1, rate), Eigen::VectorXd::Constant(1, temp_c));
    for (std::size_t k = 0; k < columns_.size(); ++k) out[k] = c(0, columns_[k]);
  }
  std::vector<double> linear_start() const override { return std::vector<double>(columns_.size(), 0.0); }
  std::vector<std::string> linear_names() const override {
    std::vector<std::string> out;
    for (int k = 1; k <= options_.sf_temperature_order; ++k) out.push_back(str_cat("sf_temperature_", k));
    for (int k = 1; k <= options_.sf_rate_order; ++k) out.push_back(str_cat("sf_rate_", k));
    for (int i = 1; i <= options_.sf_cross_order; ++i)
      for (int k = 1; k <= options_.sf_rate_order; ++k) out.push_back(str_cat("sf_cross_", i, "_", k));
    return out;
  }
  std::shared_ptr<CalibrationModel> model(const std::vector<double>& linear, const std::vector<std::vector<double>>&) const override {
    Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(ClassicalColumns(options_).size());
    for (std::size_t k = 0; k < columns_.size(); ++k) coefficients(columns_[k]) = linear[k];
    auto m = std::make_shared<ClassicalModel>(shape_);
    m->set_coefficients(options_, coefficients);
    return m;
  }

 private:
  ClassicalOptions options_;
  ClassicalModel shape_;               // scaling only; coefficients unused
  std::vector<Eigen::Index> columns_;  // of classical_columns, one per linear parameter
};

class RbfTerm : public SurfaceTerm {
 public:
  RbfTerm(const RbfNetwork& start, Eigen::MatrixXd penalty, Eigen::VectorXd target)
      : start_(start), penalty_(std::move(penalty)), target_(std::move(target)) {
    if (target_.size() == 0) target_ = Eigen::VectorXd::Zero(penalty_.rows());
    if (start.features() != default_features()) fail("triad: a joint RBF surface takes the inputs measured_rate, temperature");
    if (start.bias != 0.0) fail("triad: the RBF surface's constant must be folded into the triad's bias first");
    if (penalty_.size() > 0 && penalty_.cols() != start.nodes()) {
      fail("triad: the RBF weight penalty is ", penalty_.rows(), " x ", penalty_.cols(), " for ", start.nodes(), " nodes");
    }
    if (target_.size() != penalty_.rows()) fail("triad: the RBF weight penalty has ", penalty_.rows(), " rows and ", target_.size(), " targets");
    if (start.output_factor > 0) fail("triad: a joint RBF surface's output factor must be its measured rate");
  }
  int nodes() const override { return static_cast<int>(start_.nodes()); }
  int node_size() const override { return static_cast<int>(NodeBlock<double>::size(start_.dimension())); }
  std::vector<double> node_start(int j) const override {
    std::vector<double> b(static_cast<std::size_t>(node_size()));
    start_.pack_node(j, b.data());
    return b;
  }
  // The normalised inputs, then (scaled by the rate) the raw rate.
  bool scaled() const { return start_.output_factor == 0; }
  int input_size() const override { return static_cast<int>(start_.dimension()) + (scaled() ? 1 : 0); }
  void inputs(double rate, double temp_c, double* x) const override {
    const double raw[2] = {rate, temp_c};
    start_.normalizer.apply(raw, x);
    if (scaled()) x[start_.dimension()] = rate;
  }
  double node_output(const double* x, const double* block, double* gradient) const override {
    const double out = gyrosid::node_output(x, {block, start_.dimension()}, gradient);
    if (!scaled()) return out;
    const double g = x[start_.dimension()];
    if (gradient)
      for (int e = 0; e < node_size(); ++e) gradient[e] *= g;
    return g * out;
  }
  const Eigen::MatrixXd& weight_penalty() const override { return penalty_; }
  const Eigen::VectorXd& weight_target() const override { return target_; }
  std::shared_ptr<CalibrationModel> model(const std::vector<double>&, const std::vector<std::vector<double>>& nodes) const override {
    auto net = std::make_shared<RbfNetwork>(start_);
    for (int j = 0; j < this->nodes(); ++j) net->unpack_node(j, nodes[static_cast<std::size_t>(j)].data());
    return net;
  }

 private:
  RbfNetwork start_;
  Eigen::MatrixXd penalty_;
  Eigen::VectorXd target_;
};

}  // namespace

std::unique_ptr<SurfaceTerm> classical_term(const ClassicalOptions& options, const Eigen::VectorXd& rates, const Eigen::VectorXd& temps) {
  if (auto p = options.validate(); !p.empty()) fail("triad classical surface: ", p);
  return std::make_unique<ClassicalTerm>(options, rates, temps);
}

std::unique_ptr<SurfaceTerm> rbf_term(const RbfNetwork& start, Eigen::MatrixXd penalty, Eigen::VectorXd target) {
  return std::make_unique<RbfTerm>(start, std::move(penalty), std::move(target));
}

Eigen::MatrixXd ols_ridge_penalty(const Eigen::MatrixXd& h, double lambda) {
  if (!(lambda > 0.0) || h.cols() == 0) return {};
  const Eigen::MatrixXd r = h.householderQr().matrixQR().topRows(h.cols()).triangularView<Eigen::Upper>();
  const Eigen::VectorXd diag = r.diagonal();
  if ((diag.array().abs() == 0.0).any()) fail("triad: the RBF surface's node columns are linearly dependent at the training inputs");
  return std::sqrt(lambda) * diag.cwiseInverse().asDiagonal() * r;
}

Eigen::MatrixXd owned_column_rows(const Eigen::MatrixXd& h, const Eigen::MatrixXd& owned, double weight) {
  if (h.cols() == 0 || owned.cols() == 0) return {};
  if (owned.rows() != h.rows()) fail("triad: ", owned.rows(), " owned-column samples for ", h.rows(), " node-column rows");
  Eigen::MatrixXd rows = owned.transpose() * h;
  for (Eigen::Index j = 0; j < owned.cols(); ++j) {
    const double norm = owned.col(j).norm();
    if (norm == 0.0) fail("triad: owned column ", j, " is zero at every training sample");
    rows.row(j) *= weight / norm;
  }
  return rows;
}

}  // namespace gyrosid
