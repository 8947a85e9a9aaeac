// Input normalisation inside a model: x~_k = (x_k - offset_k) / scale_k.
//   range:  the training range of each input mapped onto [-1, 1] (the default)
//   units:  rates in deg/s, everything else as is - the thesis's raw inputs (Orr's toolbox worked on deg/s and
//           deg C directly, so its node "scale" 17.5 is a width in those units)
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.h"

namespace gyrosid {

enum class NormalizationKind { range, units };

template <>
struct EnumNames<NormalizationKind> {
  static constexpr std::string_view kNoun = "input normalisation";
  static constexpr std::array<std::pair<NormalizationKind, std::string_view>, 2> kTable{
      {{NormalizationKind::range, "range"}, {NormalizationKind::units, "units"}}};
};

struct Normalizer {
  Eigen::VectorXd offset;
  Eigen::VectorXd scale;

  static Normalizer make(NormalizationKind kind, const std::vector<std::string>& features, const Eigen::MatrixXd& x);
  Eigen::Index dimension() const { return offset.size(); }
  Eigen::MatrixXd apply(const Eigen::MatrixXd& x) const;  // rows are samples
  void apply(const double* x, double* out) const;
  nlohmann::json to_json() const;
  static Normalizer from_json(const nlohmann::json& j);
};

}  // namespace gyrosid
