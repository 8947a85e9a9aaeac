#include "model/averaging_bias.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

std::vector<SpreadInput> gyro_spread_inputs(const Decimation& decimation) {
  std::vector<SpreadInput> out;
  for (const InputSpread& s : decimation.inputs) {
    if (s.column.ends_with("_dps")) out.push_back({"measured_rate", s.column, units::kDegToRad});
    if (s.column.ends_with("_c")) out.push_back({"temperature", s.column, 1.0});
  }
  return out;
}

namespace {

// bias_i of one input, rad/s (zero when the model does not read it or it does not vary).
Eigen::VectorXd input_bias(const CalibrationModel& model, const Dataset& data, const Eigen::VectorXd& at_mean, const SpreadInput& input,
                           const InputSpread* spread) {
  const auto feature = std::find(data.features.begin(), data.features.end(), input.feature);
  if (feature == data.features.end() || !spread || !(spread->max_sd > 0)) return Eigen::VectorXd::Zero(data.size());
  if (static_cast<Eigen::Index>(spread->sd.size()) != data.size()) {
    fail("averaging bias: ", spread->sd.size(), " block spreads of ", input.column, " for ", data.size(), " samples");
  }
  const Eigen::Index k = feature - data.features.begin();
  const double shift = spread->max_sd * input.scale;
  const bool rate = input.feature == "measured_rate";
  Dataset shifted = data;
  shifted.x.col(k).array() += shift;
  if (rate) shifted.measured.array() += shift;
  const Eigen::VectorXd up = model.predict(shifted);
  shifted.x.col(k).array() -= 2.0 * shift;
  if (rate) shifted.measured.array() -= 2.0 * shift;
  const Eigen::VectorXd down = model.predict(shifted);
  const Eigen::ArrayXd ratio = Eigen::Map<const Eigen::ArrayXd>(spread->sd.data(), data.size()) / spread->max_sd;
  return (ratio.square() * (0.5 * (up + down) - at_mean).array()).matrix();
}

}  // namespace

AveragingBias averaging_bias(const CalibrationModel& model, const Dataset& data, const Decimation& decimation, double residual_rms_dph) {
  AveragingBias out;
  out.blocks = static_cast<std::size_t>(data.size());
  out.threshold_dph = 0.1 * residual_rms_dph;
  if (!decimation.applied() || data.size() == 0) return out;
  const Eigen::VectorXd at_mean = model.predict(data);
  Eigen::VectorXd bias = Eigen::VectorXd::Zero(data.size());
  for (const SpreadInput& input : gyro_spread_inputs(decimation)) bias += input_bias(model, data, at_mean, input, decimation.spread(input.column));
  const Eigen::ArrayXd dph = bias.array().abs() * units::radps_to_dph(1.0);
  out.largest_dph = dph.maxCoeff();
  out.blocks_over = static_cast<std::size_t>((dph > out.threshold_dph).count());
  return out;
}

std::string AveragingBias::statement() const {
  return str_cat("the fitted model's curvature makes the averaging bias (f'' var / 2) at most ", format_significant(largest_dph, 3),
                 " deg/h, over a tenth of the residual rms (", format_significant(threshold_dph, 3), " deg/h) in ", blocks_over, " of ",
                 blocks, " blocks");
}

nlohmann::json AveragingBias::to_json() const {
  return {{"largest_dph", largest_dph}, {"threshold_dph", threshold_dph}, {"blocks_over", blocks_over}, {"blocks", blocks}};
}

nlohmann::json decimation_summary(const Decimation& decimation, const AveragingBias& bias) {
  nlohmann::json j = decimation.to_json();
  j["averaging_bias"] = bias.to_json();
  j["statement"] = decimation.statement() + "; " + bias.statement();
  return j;
}

}  // namespace gyrosid
