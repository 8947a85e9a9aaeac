#include "model/held_inputs.h"

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {

HeldInputs held_inputs(const Eigen::VectorXd& rate_radps, const Eigen::VectorXd& temp_c) {
  HeldInputs h;
  if (rate_radps.size() == 0) return h;
  h.temp_span_c = temp_c.maxCoeff() - temp_c.minCoeff(), h.temp_mean_c = temp_c.mean();
  h.rate_span_dps = units::radps_to_dps(rate_radps.maxCoeff() - rate_radps.minCoeff());
  h.rate_mean_dps = units::radps_to_dps(rate_radps.mean());
  h.temperature = h.temp_span_c < kHeldTemperatureSpanC, h.rate = h.rate_span_dps < kHeldRateSpanDps;
  return h;
}

std::string HeldInputs::held() const {
  std::string why;
  if (temperature) why = str_cat("the temperature stays within ", format_significant(temp_span_c, 2), " C of ", format_significant(temp_mean_c, 3), " C");
  if (rate) {
    why += str_cat(why.empty() ? "" : " and ", "the rate within ", format_significant(rate_span_dps, 2), " deg/s of ",
                   format_significant(rate_mean_dps, 3), " deg/s");
  }
  return why;
}

namespace {

std::string consequences(const HeldInputs& h) {
  return str_cat(h.temperature ? "; the calibration holds at this temperature only" : "", h.rate ? "; the scale factor is not calibrated" : "");
}

}  // namespace

std::string HeldInputs::left_out_note(const std::vector<std::string>& left_out) const {
  const std::string why = held();
  return str_cat(why, why.empty() ? "" : ": ", "the recording does not determine ", join(left_out), " - left out of the physics",
                 consequences(*this));
}

std::string HeldInputs::ridge_note() const {
  return str_cat(held(), ": the ridge, not the recording, sets the terms in ", temperature && rate ? "them" : "it", consequences(*this));
}

}  // namespace gyrosid
