#include "model/averaging_bias.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"

namespace gyrosid {

std::vector<SpreadInput> gyro_spread_inputs() {
  return {{"measured_rate", "ref_rate_dps", units::kDegToRad}, {"temperature", "temp_c", 1.0}};
}

double largest_averaging_bias(const CalibrationModel& model, const Dataset& data, const Decimation& decimation,
                              const std::vector<SpreadInput>& inputs) {
  if (!decimation.applied() || data.size() == 0) return 0.0;
  const Eigen::VectorXd at_mean = model.predict(data);
  Eigen::VectorXd bias = Eigen::VectorXd::Zero(data.size());
  for (const SpreadInput& input : inputs) {
    const auto feature = std::find(data.features.begin(), data.features.end(), input.feature);
    const InputSpread* spread = decimation.spread(input.column);
    if (feature == data.features.end() || !spread || !(spread->max_sd > 0)) continue;
    if (static_cast<Eigen::Index>(spread->sd.size()) != data.size()) {
      fail("averaging bias: ", spread->sd.size(), " block spreads of ", input.column, " for ", data.size(), " samples");
    }
    const Eigen::Index k = feature - data.features.begin();
    const Eigen::VectorXd s = Eigen::Map<const Eigen::VectorXd>(spread->sd.data(), data.size()) * input.scale;
    Dataset shifted = data;
    shifted.x.col(k) = data.x.col(k) + s;
    if (input.feature == "measured_rate") shifted.measured = data.measured + s;
    const Eigen::VectorXd up = model.predict(shifted);
    shifted.x.col(k) = data.x.col(k) - s;
    if (input.feature == "measured_rate") shifted.measured = data.measured - s;
    const Eigen::VectorXd down = model.predict(shifted);
    bias += 0.5 * (up + down) - at_mean;
  }
  return bias.size() ? bias.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace gyrosid
