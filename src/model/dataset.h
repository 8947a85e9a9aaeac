// Training and evaluation data for calibration models, extracted from a single-gyro recording.
//
// A calibration model maps the gyro's measured inputs to its rate error (thesis fig 4.17/4.19) or to the
// corrected rate (fig 4.18). Inputs ("features") are named; values are SI (rad/s, deg C, deg C/s) or the
// unit of an auxiliary column:
//   measured_rate     gyro_dps, the raw gyro output                      rad/s
//   temperature       temp_c, the package probe                          deg C
//   temperature_rate  d(temp_c)/dt, central differences on the samples   deg C/s
//   <column name>     any other recording column, as recorded (e.g. supply_v)
// Targets: error = gyro - ref (rad/s); corrected_rate = ref (rad/s).
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.h"
#include "core/recording.h"

namespace gyrosid {

enum class ModelTarget { error, corrected_rate };

template <>
struct EnumNames<ModelTarget> {
  static constexpr std::string_view kNoun = "model target";
  static constexpr std::array<std::pair<ModelTarget, std::string_view>, 2> kTable{
      {{ModelTarget::error, "error"}, {ModelTarget::corrected_rate, "corrected_rate"}}};
};

struct Dataset {
  std::vector<std::string> features;  // column meaning of x
  Eigen::MatrixXd x;                  // N x d inputs
  Eigen::VectorXd target;             // N, rad/s
  Eigen::VectorXd measured;           // N, the raw gyro rate (rad/s), for compensation
  Eigen::VectorXd reference;          // N, the true rate (rad/s) where recorded, else NaN
  std::vector<double> t_s;

  Eigen::Index size() const { return x.rows(); }
};

inline const std::vector<std::string>& default_features() {
  static const std::vector<std::string> f{"measured_rate", "temperature"};
  return f;
}

// Builds the inputs (and, when the recording has ref_rate_dps, the target) of a single-gyro recording.
// Errors name the recording and the missing column.
Dataset make_dataset(const Recording& recording, const std::vector<std::string>& features, ModelTarget target);

// d(values)/dt by central differences (one-sided at the ends), for non-uniform times.
std::vector<double> time_derivative(const std::vector<double>& t, const std::vector<double>& values);

}  // namespace gyrosid
