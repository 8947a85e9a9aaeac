#include "model/dataset.h"

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

std::vector<double> time_derivative(const std::vector<double>& t, const std::vector<double>& v) {
  const std::size_t n = v.size();
  std::vector<double> d(n, 0.0);
  if (n < 2) return d;
  d.front() = (v[1] - v[0]) / (t[1] - t[0]);
  d.back() = (v[n - 1] - v[n - 2]) / (t[n - 1] - t[n - 2]);
  for (std::size_t i = 1; i + 1 < n; ++i) d[i] = (v[i + 1] - v[i - 1]) / (t[i + 1] - t[i - 1]);
  return d;
}

Dataset make_dataset(const Recording& rec, const std::vector<std::string>& features, ModelTarget target) {
  if (rec.kind() != RecordingKind::single) {
    fail(rec.source(), ": calibration models are fitted per gyro; this is a triad recording (choose the gyro with --axis x|y|z)");
  }
  if (features.empty()) fail(rec.source(), ": a model needs at least one input feature");
  Dataset d;
  d.features = features;
  d.t_s = rec.column("t_s");
  const Eigen::Index n = static_cast<Eigen::Index>(rec.rows());
  d.x.resize(n, static_cast<Eigen::Index>(features.size()));
  const auto& gyro = rec.column("gyro_dps");
  d.measured.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) d.measured(i) = units::dps_to_radps(gyro[i]);
  std::vector<double> temp_rate;
  for (std::size_t f = 0; f < features.size(); ++f) {
    const std::string& name = features[f];
    const auto col = static_cast<Eigen::Index>(f);
    if (name == "temperature" || name == "temperature_rate") {
      require_column(rec, "temp_c", str_cat("the model takes the ", name == "temperature" ? "temperature" : "temperature's rate",
                                            " as an input (feature '", name, "'); record it, or choose features without it (--features)"));
    }
    if (name == "measured_rate") {
      d.x.col(col) = d.measured;
    } else if (name == "temperature") {
      const auto& temp = rec.column("temp_c");
      for (Eigen::Index i = 0; i < n; ++i) d.x(i, col) = temp[i];
    } else if (name == "temperature_rate") {
      if (temp_rate.empty()) temp_rate = time_derivative(d.t_s, rec.column("temp_c"));
      for (Eigen::Index i = 0; i < n; ++i) d.x(i, col) = temp_rate[i];
    } else if (rec.has(name)) {
      const auto& aux = rec.column(name);
      for (Eigen::Index i = 0; i < n; ++i) {
        if (std::isnan(aux[i])) fail(rec.row_location(i), ": feature column '", name, "' is nan (not measured)");
        d.x(i, col) = aux[i];
      }
    } else {
      fail(rec.source(), ": unknown feature '", name,
           "'; known: measured_rate, temperature, temperature_rate, or a column of the recording");
    }
  }
  d.reference = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  if (rec.has("ref_rate_dps")) {
    const auto& ref = rec.column("ref_rate_dps");
    for (Eigen::Index i = 0; i < n; ++i) d.reference(i) = units::dps_to_radps(ref[i]);
  }
  d.target = target == ModelTarget::error ? Eigen::VectorXd(d.measured - d.reference) : d.reference;
  return d;
}

}  // namespace gyrosid
