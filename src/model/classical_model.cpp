#include "model/classical_model.h"

#include <Eigen/QR>

#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "model/fit_notes.h"
#include "model/held_inputs.h"

namespace gyrosid {

std::string ClassicalOptions::validate() const {
  if (bias_order < 0 || bias_order > 8) return str_cat("bias_order = ", bias_order, " must be in [0, 8]");
  if (sf_temperature_order < 0 || sf_temperature_order > 6) return str_cat("sf_temperature_order = ", sf_temperature_order, " must be in [0, 6]");
  if (sf_rate_order < 0 || sf_rate_order > 10) return str_cat("sf_rate_order = ", sf_rate_order, " must be in [0, 10]");
  if (sf_cross_order < 0 || sf_cross_order > 4) return str_cat("sf_cross_order = ", sf_cross_order, " must be in [0, 4]");
  return "";
}

ClassicalModel::ClassicalModel(std::vector<std::string> features, ModelTarget target)
    : CalibrationModel(std::move(features), target) {}

namespace {

double horner(const Eigen::VectorXd& c, double x) {
  double v = 0.0;
  for (Eigen::Index i = c.size(); i-- > 0;) v = v * x + c(i);
  return v;
}

std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
Eigen::VectorXd from_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

double ClassicalModel::predict(const double* x) const {
  const double w = x[0];
  const double u = w / rate_scale, v = (x[1] - temperature_reference) / temperature_scale;
  double cross = 0.0, vp = 1.0;
  for (Eigen::Index i = 0; i < sf_cross.rows(); ++i) {
    vp *= v;
    double up = 1.0, row = 0.0;
    for (Eigen::Index k = 0; k < sf_cross.cols(); ++k) row += sf_cross(i, k) * (up *= u);
    cross += vp * row;
  }
  return horner(bias, v) + (horner(sf_temperature, v) + horner(sf_rate, u) + cross) * w;
}

nlohmann::json ClassicalModel::parameters_json() const {
  nlohmann::json j = {{"rate_scale_radps", rate_scale},
          {"temperature_reference_c", temperature_reference},
          {"temperature_scale_c", temperature_scale},
          {"bias_radps", to_vector(bias)},
          {"sf_temperature", to_vector(sf_temperature)},
          {"sf_rate", to_vector(sf_rate)}};
  if (sf_cross.size() > 0) {
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index i = 0; i < sf_cross.rows(); ++i) rows.push_back(to_vector(sf_cross.row(i).transpose()));
    j["sf_cross"] = rows;
  }
  return j;
}

std::unique_ptr<ClassicalModel> ClassicalModel::from_json(const nlohmann::json& j, std::vector<std::string> features,
                                                          ModelTarget target) {
  if (features.size() != 2 || features[0] != "measured_rate" || features[1] != "temperature") {
    fail("classical model: features must be [measured_rate, temperature]");
  }
  auto m = std::make_unique<ClassicalModel>(std::move(features), target);
  m->rate_scale = j.at("rate_scale_radps").get<double>();
  m->temperature_reference = j.at("temperature_reference_c").get<double>();
  m->temperature_scale = j.at("temperature_scale_c").get<double>();
  m->bias = from_vector(j.at("bias_radps").get<std::vector<double>>());
  m->sf_temperature = from_vector(j.at("sf_temperature").get<std::vector<double>>());
  m->sf_rate = from_vector(j.at("sf_rate").get<std::vector<double>>());
  if (j.contains("sf_cross")) {  // optional: absent in separable models (and in files before it existed)
    const auto rows = j.at("sf_cross").get<std::vector<std::vector<double>>>();
    const std::size_t cols = rows.empty() ? 0 : rows[0].size();
    m->sf_cross = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i].size() != cols) fail("classical model: sf_cross rows must have equal lengths");
      for (std::size_t k = 0; k < cols; ++k) m->sf_cross(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k];
    }
  }
  if (!(m->rate_scale > 0 && m->temperature_scale > 0)) fail("classical model: scales must be positive");
  return m;
}

void ClassicalModel::export_c_body(CExport& out) const {
  out.array("bias", bias.data(), static_cast<std::size_t>(bias.size()));
  out.array("sf_temperature", sf_temperature.data(), static_cast<std::size_t>(sf_temperature.size()));
  out.array("sf_rate", sf_rate.data(), static_cast<std::size_t>(sf_rate.size()));
  std::vector<double> cross;  // row-major gamma_ik
  for (Eigen::Index i = 0; i < sf_cross.rows(); ++i)
    for (Eigen::Index k = 0; k < sf_cross.cols(); ++k) cross.push_back(sf_cross(i, k));
  if (!cross.empty()) out.array("sf_cross", cross.data(), cross.size());
  const std::string p = out.prefix;
  out.source << "\nstatic double " << p << "_horner(const double* c, int n, double x) {\n"
             << "  double v = 0.0;\n  int i;\n  for (i = n - 1; i >= 0; --i) v = v * x + c[i];\n  return v;\n}\n\n"
             << "/* Classical compensation: b(T) + (s_T(T) + s_w(w)) w. */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  const double w = x[0];\n"
             << "  const double u = w / " << std::hexfloat << rate_scale << ";\n"
             << "  const double v = (x[1] - " << temperature_reference << ") / " << temperature_scale << ";\n"
             << std::defaultfloat;
  std::string cross_term;
  if (!cross.empty()) {  // s_wT = sum_i v^i u sum_k gamma_ik u^(k-1)
    out.source << "  double cross = 0.0, vp = 1.0;\n  int i;\n"
               << "  for (i = 0; i < " << sf_cross.rows() << "; ++i) {\n    vp *= v;\n"
               << "    cross += vp * u * " << p << "_horner(" << p << "_sf_cross + i * " << sf_cross.cols() << ", " << sf_cross.cols() << ", u);\n  }\n";
    cross_term = " + cross";
  }
  out.source << "  return " << p << "_horner(" << p << "_bias, " << bias.size() << ", v) + (" << p << "_horner(" << p
             << "_sf_temperature, " << sf_temperature.size() << ", v) + " << p << "_horner(" << p << "_sf_rate, "
             << sf_rate.size() << ", u)" << cross_term << ") * w;\n}\n";
}

ClassicalColumns::ClassicalColumns(const ClassicalOptions& o)
    : bias{0, o.bias_order + 1},
      sf_temperature{bias.end(), o.sf_temperature_order},
      sf_rate{sf_temperature.end(), o.sf_rate_order + 1},
      sf_cross{sf_rate.end(), static_cast<Eigen::Index>(o.sf_cross_order) * o.sf_rate_order} {}

void ClassicalModel::set_coefficients(const ClassicalOptions& o, const Eigen::VectorXd& coefficients) {
  const ClassicalColumns g(o);
  if (coefficients.size() != g.size()) fail("classical model: ", coefficients.size(), " coefficients for ", g.size(), " columns");
  const auto group = [&](const ClassicalColumns::Group& at) { return coefficients.segment(at.first, at.count); };
  bias = group(g.bias);
  sf_temperature = Eigen::VectorXd::Zero(g.sf_temperature.count + 1);
  sf_temperature.tail(g.sf_temperature.count) = group(g.sf_temperature);
  sf_rate = group(g.sf_rate);
  sf_cross = Eigen::Map<const Eigen::MatrixXd>(coefficients.data() + g.sf_cross.first, o.sf_rate_order, o.sf_cross_order).transpose();
}

// Columns of the additive model in ClassicalColumns' order (no cross terms for the separable model).
Eigen::MatrixXd classical_columns(const ClassicalModel& m, const ClassicalOptions& o, const Eigen::VectorXd& w,
                                  const Eigen::VectorXd& temp) {
  const int nb = o.bias_order, nt = o.sf_temperature_order, nw = o.sf_rate_order, nc = o.sf_cross_order;
  Eigen::MatrixXd a(w.size(), ClassicalColumns(o).size());
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    const double u = w(i) / m.rate_scale, v = (temp(i) - m.temperature_reference) / m.temperature_scale;
    Eigen::Index c = 0;
    double vp = 1.0;
    for (int k = 0; k <= nb; ++k, vp *= v) a(i, c++) = vp;
    vp = v;
    for (int k = 1; k <= nt; ++k, vp *= v) a(i, c++) = vp * w(i);
    double up = 1.0;
    for (int k = 0; k <= nw; ++k, up *= u) a(i, c++) = up * w(i);
    vp = 1.0;
    for (int j = 1; j <= nc; ++j) {
      vp *= v;
      up = 1.0;
      for (int k = 1; k <= nw; ++k) a(i, c++) = vp * (up *= u) * w(i);
    }
  }
  return a;
}

namespace {

// Names of classical_columns' columns, after the model file's fields.
std::vector<std::string> classical_column_names(const ClassicalOptions& o) {
  std::vector<std::string> out;
  for (int k = 0; k <= o.bias_order; ++k) out.push_back(str_cat("bias v^", k));
  for (int k = 1; k <= o.sf_temperature_order; ++k) out.push_back(str_cat("sf_temperature v^", k));
  for (int k = 0; k <= o.sf_rate_order; ++k) out.push_back(str_cat("sf_rate u^", k));
  for (int j = 1; j <= o.sf_cross_order; ++j)
    for (int k = 1; k <= o.sf_rate_order; ++k) out.push_back(str_cat("sf_cross v^", j, " u^", k));
  return out;
}

// The inputs column c of classical_columns depends on: the bias's v^k (k >= 1) on the temperature, every
// scale-factor column on the rate, sf_temperature's and sf_cross's on both.
struct ColumnInputs {
  bool temperature = false, rate = false;
};
ColumnInputs classical_column_inputs(const ClassicalOptions& o, Eigen::Index c) {
  const ClassicalColumns g(o);
  if (c < g.bias.end()) return {c > g.bias.first, false};
  return {c < g.sf_temperature.end() || c >= g.sf_cross.first, true};
}

}  // namespace

std::unique_ptr<ClassicalModel> fit_classical(const Dataset& data, const ClassicalOptions& o, SolveSummary* summary) {
  if (auto p = o.validate(); !p.empty()) fail("classical model: ", p);
  if (data.features.size() != 2 || data.features[0] != "measured_rate" || data.features[1] != "temperature") {
    fail("classical model: features must be measured_rate, temperature");
  }
  if (!data.target.allFinite()) fail("classical model: the recording has no reference rate (ref_rate_dps) to fit against");
  auto model = std::make_unique<ClassicalModel>(data.features, ModelTarget::error);
  const SolveSummary s = timed_solve("classical", [&](SolveMonitor& monitor) {
    const Eigen::VectorXd w = data.x.col(0), temp = data.x.col(1);
    model->rate_scale = std::max(w.cwiseAbs().maxCoeff(), 1e-6);
    model->temperature_reference = 0.5 * (temp.maxCoeff() + temp.minCoeff());
    model->temperature_scale = std::max(0.5 * (temp.maxCoeff() - temp.minCoeff()), 1.0);
    const Eigen::MatrixXd all = classical_columns(*model, o, w, temp);
    // Columns in an input the recording holds are left out (coefficient 0): on a recording at rest the
    // rate columns would otherwise fit the noise in the measured rate (held_inputs.h).
    const HeldInputs held = held_inputs(data.reference, temp);
    std::vector<Eigen::Index> kept;
    std::vector<std::string> left_out;
    const std::vector<std::string> names = classical_column_names(o);
    for (Eigen::Index c = 0; c < all.cols(); ++c) {
      const ColumnInputs in = classical_column_inputs(o, c);
      if ((held.temperature && in.temperature) || (held.rate && in.rate)) left_out.push_back(names[static_cast<std::size_t>(c)]);
      else kept.push_back(c);
    }
    const Eigen::MatrixXd a = all(Eigen::all, kept);
    const Eigen::Index p = a.cols(), n = data.size();
    if (n < 2 * p) fail("classical model: ", n, " samples for ", p, " coefficients");
    // Column scaling, then pivoted QR.
    const Eigen::VectorXd col_norm = a.colwise().norm().transpose().cwiseMax(1e-300);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a * col_norm.cwiseInverse().asDiagonal());
    if (qr.rank() < p) fail("classical model: the recording does not determine all ", p, " coefficients (rank ", qr.rank(), "); lower the polynomial orders or cover more temperatures and rates");
    Eigen::VectorXd coeff = Eigen::VectorXd::Zero(all.cols());
    coeff(kept) = qr.solve(data.target).cwiseQuotient(col_norm);
    model->set_coefficients(o, coeff);
    const double rss = (all * coeff - data.target).squaredNorm();
    monitor.iteration(0.5 * rss);
    const auto diag = qr.matrixR().diagonal().cwiseAbs();
    nlohmann::json details = {{"samples", n},
                              {"rms_residual_dph", units::radps_to_dph(std::sqrt(rss / static_cast<double>(n)))},
                              {"condition_estimate", diag.maxCoeff() / diag.minCoeff()}};
    FitNotes notes;
    notes.parameters = static_cast<int>(p);
    if (!left_out.empty()) notes.physics_left_out = PhysicsLeftOut{left_out, held.left_out_note(left_out)};
    write_fit_notes(notes, details);
    return SolveOutcome{Termination::converged, "linear least squares by column-pivoted QR", details};
  });
  if (summary) *summary = s;
  return model;
}

}  // namespace gyrosid
