#include "model/classical_model.h"

#include <Eigen/QR>

#include <cmath>

#include "core/error.h"
#include "core/units.h"

namespace gyrosid {

std::string ClassicalOptions::validate() const {
  if (bias_order < 0 || bias_order > 8) return str_cat("bias_order = ", bias_order, " must be in [0, 8]");
  if (sf_temperature_order < 0 || sf_temperature_order > 6) return str_cat("sf_temperature_order = ", sf_temperature_order, " must be in [0, 6]");
  if (sf_rate_order < 0 || sf_rate_order > 10) return str_cat("sf_rate_order = ", sf_rate_order, " must be in [0, 10]");
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
  return horner(bias, v) + (horner(sf_temperature, v) + horner(sf_rate, u)) * w;
}

nlohmann::json ClassicalModel::parameters_json() const {
  return {{"rate_scale_radps", rate_scale},
          {"temperature_reference_c", temperature_reference},
          {"temperature_scale_c", temperature_scale},
          {"bias_radps", to_vector(bias)},
          {"sf_temperature", to_vector(sf_temperature)},
          {"sf_rate", to_vector(sf_rate)}};
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
  if (!(m->rate_scale > 0 && m->temperature_scale > 0)) fail("classical model: scales must be positive");
  return m;
}

void ClassicalModel::export_c_body(CExport& out) const {
  out.array("bias", bias.data(), static_cast<std::size_t>(bias.size()));
  out.array("sf_temperature", sf_temperature.data(), static_cast<std::size_t>(sf_temperature.size()));
  out.array("sf_rate", sf_rate.data(), static_cast<std::size_t>(sf_rate.size()));
  const std::string p = out.prefix;
  out.source << "\nstatic double " << p << "_horner(const double* c, int n, double x) {\n"
             << "  double v = 0.0;\n  int i;\n  for (i = n - 1; i >= 0; --i) v = v * x + c[i];\n  return v;\n}\n\n"
             << "/* Classical compensation: b(T) + (s_T(T) + s_w(w)) w. */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  const double w = x[0];\n"
             << "  const double u = w / " << std::hexfloat << rate_scale << ";\n"
             << "  const double v = (x[1] - " << temperature_reference << ") / " << temperature_scale << ";\n"
             << std::defaultfloat
             << "  return " << p << "_horner(" << p << "_bias, " << bias.size() << ", v) + (" << p << "_horner(" << p
             << "_sf_temperature, " << sf_temperature.size() << ", v) + " << p << "_horner(" << p << "_sf_rate, "
             << sf_rate.size() << ", u)) * w;\n}\n";
}

// Columns of the additive separable model: v^0..v^nb | v^1..v^nt w | u^0..u^nw w.
Eigen::MatrixXd classical_columns(const ClassicalModel& m, const ClassicalOptions& o, const Eigen::VectorXd& w,
                                  const Eigen::VectorXd& temp) {
  const int nb = o.bias_order, nt = o.sf_temperature_order, nw = o.sf_rate_order;
  Eigen::MatrixXd a(w.size(), (nb + 1) + nt + (nw + 1));
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    const double u = w(i) / m.rate_scale, v = (temp(i) - m.temperature_reference) / m.temperature_scale;
    Eigen::Index c = 0;
    double vp = 1.0;
    for (int k = 0; k <= nb; ++k, vp *= v) a(i, c++) = vp;
    vp = v;
    for (int k = 1; k <= nt; ++k, vp *= v) a(i, c++) = vp * w(i);
    double up = 1.0;
    for (int k = 0; k <= nw; ++k, up *= u) a(i, c++) = up * w(i);
  }
  return a;
}

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
    const Eigen::MatrixXd a = classical_columns(*model, o, w, temp);
    const Eigen::Index p = a.cols(), n = data.size();
    if (n < 2 * p) fail("classical model: ", n, " samples for ", p, " coefficients");
    // Column scaling, then pivoted QR.
    const Eigen::VectorXd col_norm = a.colwise().norm().transpose().cwiseMax(1e-300);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a * col_norm.cwiseInverse().asDiagonal());
    if (qr.rank() < p) fail("classical model: the recording does not determine all ", p, " coefficients (rank ", qr.rank(), "); lower the polynomial orders or cover more temperatures and rates");
    const Eigen::VectorXd coeff = qr.solve(data.target).cwiseQuotient(col_norm);
    const int nb = o.bias_order, nt = o.sf_temperature_order, nw = o.sf_rate_order;
    model->bias = coeff.head(nb + 1);
    model->sf_temperature = Eigen::VectorXd::Zero(nt + 1);
    model->sf_temperature.tail(nt) = coeff.segment(nb + 1, nt);
    model->sf_rate = coeff.tail(nw + 1);
    const double rss = (a * coeff - data.target).squaredNorm();
    monitor.iteration(0.5 * rss);
    const auto diag = qr.matrixR().diagonal().cwiseAbs();
    return SolveOutcome{Termination::converged, "linear least squares by column-pivoted QR",
                        {{"samples", n}, {"parameters", p},
                         {"rms_residual_dph", units::radps_to_dph(std::sqrt(rss / static_cast<double>(n)))},
                         {"condition_estimate", diag.maxCoeff() / diag.minCoeff()}}};
  });
  if (summary) *summary = s;
  return model;
}

}  // namespace gyrosid
