#include "model/calibration_model.h"

#include <cmath>
#include <iomanip>

#include "core/atomic_file.h"
#include "core/error.h"

namespace gyrosid {

void CExport::array(const std::string& name, const double* values, std::size_t count) {
  source << "static const double " << id(name) << "[" << std::max<std::size_t>(count, 1) << "] = {";
  for (std::size_t i = 0; i < count; ++i) {
    if (i % 4 == 0) source << "\n   ";
    source << " " << std::hexfloat << values[i] << std::defaultfloat << (i + 1 < count ? "," : "");
  }
  if (count == 0) source << "0.0";
  source << "};\n";
}

Eigen::VectorXd CalibrationModel::predict(const Dataset& data) const {
  Eigen::VectorXd out(data.size());
  std::vector<double> row(static_cast<std::size_t>(data.x.cols()));
  for (Eigen::Index i = 0; i < data.size(); ++i) {
    for (Eigen::Index k = 0; k < data.x.cols(); ++k) row[static_cast<std::size_t>(k)] = data.x(i, k);
    out(i) = predict(row.data());
  }
  return out;
}

Eigen::MatrixXd CalibrationModel::regressors(const Eigen::MatrixXd&) const {
  fail(kind(), " model: no posterior over its weights (fit it with a Bayesian solver, e.g. --solver bayes or --model hybrid)");
}

PredictionWithSigma CalibrationModel::predict_with_sigma(const Eigen::MatrixXd& x) const {
  const WeightPosterior* p = posterior();
  if (!p) regressors(x);  // the error naming the kind
  if (x.cols() != static_cast<Eigen::Index>(features().size())) {
    fail(kind(), " model: ", x.cols(), " input columns for ", features().size(), " features");
  }
  PredictionWithSigma out;
  out.value.resize(x.rows());
  std::vector<double> row(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (Eigen::Index k = 0; k < x.cols(); ++k) row[static_cast<std::size_t>(k)] = x(i, k);
    out.value(i) = predict(row.data());
  }
  out.sigma = p->sigma(regressors(x));
  return out;
}

nlohmann::json CalibrationModel::to_json() const {
  return {{"format", kModelFormat},
          {"kind", kind()},
          {"target", to_string(target())},
          {"features", features()},
          {"parameters", parameters_json()}};
}

void CalibrationModel::export_c(const std::filesystem::path& dir, const std::string& prefix) const {
  for (char c : prefix) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_') || std::isdigit(static_cast<unsigned char>(prefix.front()))) {
      fail("C export: prefix '", prefix, "' is not a C identifier");
    }
  }
  CExport out;
  out.prefix = prefix;
  std::string guard = prefix;
  for (char& c : guard) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  out.header << "/* " << prefix << ".h - gyrosid " << kind() << " calibration model, generated; dependency-free C99. */\n"
             << "#ifndef " << guard << "_H\n#define " << guard << "_H\n\n"
             << "/* Inputs x[] in this order (SI: rad/s, deg C, deg C/s):";
  for (std::size_t i = 0; i < features().size(); ++i) out.header << (i ? ", " : " ") << features()[i];
  out.header << ". */\n#define " << guard << "_NUM_INPUTS " << features().size() << "\n\n"
             << "/* Model output in rad/s: the rate " << (target() == ModelTarget::error ? "error" : "itself (corrected)") << ". */\n"
             << "double " << prefix << "_predict(const double* x);\n"
             << "/* Compensated rate, rad/s. */\n"
             << "double " << prefix << "_compensate(const double* x, double measured_radps);\n\n#endif\n";
  out.source << "/* " << prefix << ".c - gyrosid " << kind() << " calibration model, generated. */\n"
             << "#include <math.h>\n#include \"" << prefix << ".h\"\n\n";
  export_c_body(out);
  out.source << "\ndouble " << prefix << "_compensate(const double* x, double measured_radps) {\n"
             << (target() == ModelTarget::error ? "  return measured_radps - " : "  (void)measured_radps;\n  return ")
             << prefix << "_predict(x);\n}\n";
  write_file_atomic(dir / (prefix + ".h"), out.header.str());
  write_file_atomic(dir / (prefix + ".c"), out.source.str());
}

Eigen::VectorXd compensate(const CalibrationModel& model, const Dataset& data) {
  const Eigen::VectorXd p = model.predict(data);
  return model.target() == ModelTarget::error ? Eigen::VectorXd(data.measured - p) : p;
}

std::unique_ptr<CalibrationModel> model_from_json(const nlohmann::json& j, const std::string& source) {
  std::unique_ptr<SensorModel> model = sensor_model_from_json(j, source);
  if (auto* gyro = dynamic_cast<CalibrationModel*>(model.get())) {
    model.release();
    return std::unique_ptr<CalibrationModel>(gyro);
  }
  fail(source, ": a ", model->kind(), " model of ", model->gyros(), " gyros; a single gyro's model is needed here");
}

std::unique_ptr<CalibrationModel> load_model(const std::filesystem::path& path) { return model_from_json(load_model_json(path), path.string()); }

}  // namespace gyrosid
