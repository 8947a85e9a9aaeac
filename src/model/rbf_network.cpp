#include "model/rbf_network.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace gyrosid {

RbfNetwork::RbfNetwork(std::vector<std::string> features, ModelTarget target, Normalizer n)
    : CalibrationModel(std::move(features), target), normalizer(std::move(n)) {
  const Eigen::Index d = normalizer.dimension();
  centres.resize(0, d);
  widths.resize(0, d);
}

double RbfNetwork::evaluate_normalised(const double* xn) const {
  const Eigen::Index m = nodes(), d = dimension();
  double f = bias;
  for (Eigen::Index j = 0; j < m; ++j) f += weights(j) * gaussian(xn, centres.data() + j, widths.data() + j, d, m);
  return f;
}

double RbfNetwork::predict(const double* x) const {
  double xn[16];
  const Eigen::Index d = dimension();
  if (d > 16) fail("rbf: at most 16 input features");
  normalizer.apply(x, xn);
  const double f = evaluate_normalised(xn);
  return output_factor < 0 ? f : x[output_factor] * f;
}

void RbfNetwork::pack_node(Eigen::Index j, double* block) const {
  const NodeBlock<double> b{block, dimension()};
  for (Eigen::Index k = 0; k < b.d; ++k) {
    b.centre()[k] = centres(j, k);
    b.log_width()[k] = std::log(widths(j, k));
  }
  b.weight() = weights(j);
}

void RbfNetwork::unpack_node(Eigen::Index j, const double* block) {
  const NodeBlock<const double> b{block, dimension()};
  for (Eigen::Index k = 0; k < b.d; ++k) {
    centres(j, k) = b.centre()[k];
    widths(j, k) = std::exp(b.log_width()[k]);
  }
  weights(j) = b.weight();
}

Eigen::MatrixXd RbfNetwork::basis(const Eigen::MatrixXd& xn) const {
  return gaussian_columns(xn, centres, widths);
}

Eigen::MatrixXd RbfNetwork::regressors(const Eigen::MatrixXd& x) const {
  if (!weight_posterior) return CalibrationModel::regressors(x);
  Eigen::MatrixXd h(x.rows(), nodes() + 1);
  h.leftCols(nodes()) = basis(normalizer.apply(x));
  h.col(nodes()).setOnes();
  if (output_factor >= 0) h = x.col(output_factor).asDiagonal() * h;
  return h;
}

namespace {

nlohmann::json rows_of(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> row(static_cast<std::size_t>(m.cols()));
    for (Eigen::Index k = 0; k < m.cols(); ++k) row[static_cast<std::size_t>(k)] = m(i, k);
    out.push_back(row);
  }
  return out;
}

Eigen::MatrixXd matrix_of(const nlohmann::json& j, Eigen::Index cols, const char* what) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(j.size()), cols);
  for (std::size_t i = 0; i < j.size(); ++i) {
    const auto row = j[i].get<std::vector<double>>();
    if (static_cast<Eigen::Index>(row.size()) != cols) fail("rbf model: ", what, " row ", i, " has ", row.size(), " values, expected ", cols);
    for (Eigen::Index k = 0; k < cols; ++k) m(static_cast<Eigen::Index>(i), k) = row[static_cast<std::size_t>(k)];
  }
  return m;
}

}  // namespace

nlohmann::json RbfNetwork::parameters_json() const {
  nlohmann::json j = {{"normalizer", normalizer.to_json()},
                      {"centres", rows_of(centres)},
                      {"widths", rows_of(widths)},
                      {"weights_radps", std::vector<double>(weights.data(), weights.data() + weights.size())},
                      {"bias_radps", bias}};
  if (output_factor >= 0) j["output_factor"] = features()[static_cast<std::size_t>(output_factor)];
  if (weight_posterior) j["posterior"] = weight_posterior->to_json();
  return j;
}

std::unique_ptr<RbfNetwork> RbfNetwork::from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                  ModelTarget target) {
  auto net = std::make_unique<RbfNetwork>(std::move(features), target, Normalizer::from_json(j.at("normalizer")));
  const Eigen::Index d = net->normalizer.dimension();
  if (d != static_cast<Eigen::Index>(net->features().size())) fail("rbf model: normalizer dimension differs from the features");
  net->centres = matrix_of(j.at("centres"), d, "centres");
  net->widths = matrix_of(j.at("widths"), d, "widths");
  const auto w = j.at("weights_radps").get<std::vector<double>>();
  net->weights = Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
  net->bias = j.value("bias_radps", 0.0);
  if (j.contains("output_factor")) {
    const auto name = j["output_factor"].get<std::string>();
    const auto& f = net->features();
    const auto it = std::find(f.begin(), f.end(), name);
    if (it == f.end()) fail("rbf model: output_factor '", name, "' is none of its features");
    net->output_factor = it - f.begin();
  }
  if (net->centres.rows() != net->weights.size() || net->widths.rows() != net->weights.size()) {
    fail("rbf model: ", net->centres.rows(), " centres, ", net->widths.rows(), " widths, ", net->weights.size(), " weights");
  }
  if ((net->widths.array() <= 0).any()) fail("rbf model: widths must be positive");
  if (j.contains("posterior")) net->weight_posterior = WeightPosterior::from_json(j["posterior"], net->nodes() + 1, "rbf model");
  return net;
}

void RbfNetwork::export_c_body(CExport& out) const {
  const Eigen::Index m = nodes(), d = dimension();
  // Row-major copies: node j's centre is c[j*d .. j*d+d-1].
  std::vector<double> c(static_cast<std::size_t>(m * d)), r(static_cast<std::size_t>(m * d));
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index k = 0; k < d; ++k) {
      c[static_cast<std::size_t>(j * d + k)] = centres(j, k);
      r[static_cast<std::size_t>(j * d + k)] = widths(j, k);
    }
  out.array("offset", normalizer.offset.data(), static_cast<std::size_t>(d));
  out.array("scale", normalizer.scale.data(), static_cast<std::size_t>(d));
  out.array("centres", c.data(), c.size());
  out.array("widths", r.data(), r.size());
  out.array("weights", weights.data(), static_cast<std::size_t>(m));
  const std::string p = out.prefix;
  out.source << "\n/* Gaussian RBF network: f = b + sum_j w_j exp(-sum_k ((x_k - o_k)/s_k - c_jk)^2 / r_jk^2)"
             << (output_factor >= 0 ? str_cat(", output x[", output_factor, "] f (a relative error)") : std::string()) << ". */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  double xn[" << d << "];\n"
             << "  double f = " << std::hexfloat << bias << std::defaultfloat << ";\n"
             << "  int j, k;\n"
             << "  for (k = 0; k < " << d << "; ++k) xn[k] = (x[k] - " << p << "_offset[k]) / " << p << "_scale[k];\n"
             << "  for (j = 0; j < " << m << "; ++j) {\n"
             << "    double z = 0.0;\n"
             << "    for (k = 0; k < " << d << "; ++k) {\n"
             << "      const double u = (xn[k] - " << p << "_centres[j * " << d << " + k]) / " << p << "_widths[j * " << d << " + k];\n"
             << "      z += u * u;\n"
             << "    }\n"
             << "    f += " << p << "_weights[j] * exp(-z);\n"
             << "  }\n"
             << "  return " << (output_factor >= 0 ? str_cat("x[", output_factor, "] * f") : std::string("f")) << ";\n"
             << "}\n";
}

}  // namespace gyrosid
