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
  CompensatedRecording out{std::move(recording), std::nullopt, std::nullopt};
  if (data.reference.allFinite()) {
    const double n = static_cast<double>(data.size());
    out.rms_before_dph = units::radps_to_dph(std::sqrt((data.measured - data.reference).squaredNorm() / n));
    out.rms_after_dph = units::radps_to_dph(std::sqrt((comp - data.reference).squaredNorm() / n));
  }
  return out;
}

}  // namespace gyrosid
