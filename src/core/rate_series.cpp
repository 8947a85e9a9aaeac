#include "core/rate_series.h"

#include <algorithm>
#include <cmath>

#include "core/axis_view.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/recording_reader.h"
#include "core/sample_timing.h"
#include "core/units.h"

namespace gyrosid {
namespace {

// A single-gyro name mapped onto the gyro's columns (gyro_dps, ref_rate_dps, temp_c), other names as given.
std::string gyro_name(const std::string& name, const GyroColumns& g) {
  if (name == "gyro_dps") return g.gyro;
  if (name == "ref_rate_dps") return g.ref;
  if (name == "temp_c" && !g.temp.empty()) return g.temp;
  return name;
}

// The column's index and its factor to deg/h; Error naming the file and the column.
std::pair<std::size_t, double> rate_column(const RecordingReader& reader, const std::string& name) {
  const auto index = reader.find(name);
  if (!index) fail(reader.source(), ": no column '", name, "' (columns: ", join(reader.names()), ")");
  double scale = 0.0;
  if (name.size() > 4 && name.ends_with("_dps")) scale = units::kSecondsPerHour;
  if (name.size() > 4 && name.ends_with("_dph")) scale = 1.0;
  if (scale == 0.0) fail(reader.source(), ": column '", name, "' is not a rate (its name must end in _dps or _dph)");
  return {*index, scale};
}

}  // namespace

RateSeries read_rate_series(const std::filesystem::path& path, const RateSeriesRequest& request) {
  RecordingReader reader(path);
  const GyroColumns g = gyro_columns(reader.names(), request.axis, reader.source());
  RateSeries out;
  out.column = gyro_name(request.column, g);
  out.subtract = request.subtract.empty() ? "" : gyro_name(request.subtract, g);
  const auto [col, scale] = rate_column(reader, out.column);
  std::pair<std::size_t, double> sub{0, 0.0};
  if (!out.subtract.empty()) sub = rate_column(reader, out.subtract);
  const auto ref = out.subtract.empty() && out.column != g.ref ? reader.find(g.ref) : std::nullopt;
  const std::size_t t_col = *reader.find("t_s");
  UniformStepCheck steps(request.purpose);
  double lo = INFINITY, hi = -INFINITY;
  Progress progress("reading " + reader.source(), std::max<std::size_t>(reader.total_bytes(), 1));
  std::vector<double> row;
  while (reader.next(row)) {
    const std::size_t n = reader.rows();
    if (const std::string e = steps.add(row[t_col]); !e.empty()) fail(reader.source(), ":", reader.line(), ": ", e);
    out.rate_dph.push_back(row[col] * scale - (out.subtract.empty() ? 0.0 : row[sub.first] * sub.second));
    if (ref) lo = std::min(lo, row[*ref] * units::kSecondsPerHour), hi = std::max(hi, row[*ref] * units::kSecondsPerHour);
    if ((n & 0xffff) == 0) progress.update(reader.bytes_read());
  }
  progress.finish();
  out.dt_s = steps.interval(reader.source());
  if (ref) out.reference_min_dph = lo, out.reference_max_dph = hi;
  return out;
}

}  // namespace gyrosid
