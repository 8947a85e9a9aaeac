#include "core/axis_view.h"

#include <algorithm>

#include "core/error.h"

namespace gyrosid {

GyroColumns gyro_columns(const std::vector<std::string>& names, const std::string& axis, const std::string& source) {
  const auto has = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  GyroColumns g;
  if (recording_kind(names) == RecordingKind::single) {
    if (!axis.empty()) fail(source, ": --axis ", axis, " applies to triad recordings only; this is a single-gyro recording");
    if (has("temp_c")) g.temp = "temp_c";
    return g;
  }
  if (axis.empty()) fail(source, ": a triad recording; choose the gyro with --axis x|y|z");
  if (axis != "x" && axis != "y" && axis != "z") fail(source, ": --axis '", axis, "' must be x, y or z");
  g.axis = axis;
  g.gyro = "gyro_" + axis + "_dps", g.ref = "ref_rate_" + axis + "_dps";
  if (has("temp_" + axis + "_c")) g.temp = "temp_" + axis + "_c";
  else if (has("temp_c")) g.temp = "temp_c";
  return g;
}

Recording single_axis_view(Recording recording, const std::string& axis, NamedColumns* other_references) {
  const GyroColumns g = gyro_columns(recording.names(), axis, recording.source());
  if (g.axis.empty()) return recording;
  Recording view(recording.source() + " (gyro " + axis + ")");
  for (const auto& [key, value] : recording.metadata()) view.set_meta(key, value);
  for (const std::string& name : recording.names()) {
    std::vector<double> values = recording.column(name);
    if (name == g.gyro) view.set_column("gyro_dps", std::move(values));
    else if (name == g.ref) view.set_column("ref_rate_dps", std::move(values));
    else if (name == g.temp) view.set_column("temp_c", std::move(values));
    else if (name.starts_with("ref_rate_")) {
      if (other_references) other_references->emplace_back(name, std::move(values));
    } else if (!name.starts_with("gyro_") && !(name.starts_with("temp_") && name != "temp_c")) {
      if (name != "temp_c") view.set_column(name, std::move(values));
    }
  }
  return view;
}

}  // namespace gyrosid
