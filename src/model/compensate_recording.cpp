#include "model/compensate_recording.h"

#include <cmath>

#include "core/units.h"

namespace gyrosid {

CompensatedRecording compensate_recording(const CalibrationModel& model, Recording recording) {
  const Dataset data = make_dataset(recording, model.features(), model.target());
  const Eigen::VectorXd comp = compensate(model, data);
  std::vector<double> dps(static_cast<std::size_t>(comp.size()));
  for (Eigen::Index i = 0; i < comp.size(); ++i) dps[static_cast<std::size_t>(i)] = units::radps_to_dps(comp(i));
  recording.set_column("compensated_dps", dps);
  Eigen::VectorXd sigma;
  if (model.posterior()) {
    sigma = model.predict_with_sigma(data.x).sigma;
    std::vector<double> s(static_cast<std::size_t>(sigma.size()));
    for (Eigen::Index i = 0; i < sigma.size(); ++i) s[static_cast<std::size_t>(i)] = units::radps_to_dps(sigma(i));
    recording.set_column("compensated_sigma_dps", s);
  }
  CompensatedRecording out{std::move(recording), std::nullopt, std::nullopt, std::nullopt};
  if (data.reference.allFinite()) {
    const double n = static_cast<double>(data.size());
    out.rms_before_dph = units::radps_to_dph(std::sqrt((data.measured - data.reference).squaredNorm() / n));
    out.rms_after_dph = units::radps_to_dph(std::sqrt((comp - data.reference).squaredNorm() / n));
    if (sigma.size() > 0) out.coverage_95 = ((comp - data.reference).array().abs() <= 1.96 * sigma.array()).cast<double>().mean();
  }
  return out;
}

CompensatedRecording compensate_triad_recording(const TriadModel& model, Recording recording) {
  const TriadData data = make_triad_data(recording);
  const Eigen::MatrixX3d comp = model.compensate(data);
  for (int a = 0; a < 3; ++a) {
    std::vector<double> dps(static_cast<std::size_t>(comp.rows()));
    for (Eigen::Index k = 0; k < comp.rows(); ++k) dps[static_cast<std::size_t>(k)] = units::radps_to_dps(comp(k, a));
    recording.set_column(std::string("compensated_") + "xyz"[a] + "_dps", std::move(dps));
  }
  CompensatedRecording out{std::move(recording), std::nullopt, std::nullopt, std::nullopt};
  if (data.has_reference()) {
    const double n = 3.0 * static_cast<double>(data.size());
    out.rms_before_dph = units::radps_to_dph(std::sqrt((data.gyro - data.reference).squaredNorm() / n));
    out.rms_after_dph = units::radps_to_dph(std::sqrt((comp - data.reference).squaredNorm() / n));
  }
  return out;
}

}  // namespace gyrosid
