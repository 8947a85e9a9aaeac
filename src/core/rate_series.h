// One rate column of a uniformly sampled recording, read in a single pass that holds nothing else: what the
// Allan deviation needs of a recording of any length (its phase is formed from it later).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gyrosid {

struct RateSeriesRequest {
  std::string column = "gyro_dps";  // a rate column (_dps or _dph)
  std::string subtract;             // a rate column subtracted sample by sample (empty: none)
  std::string axis;                 // triads: x, y or z - gyro_dps and ref_rate_dps then name that gyro's columns
  std::string purpose = "the Allan deviation";  // for the error a non-uniform recording gets
};

struct RateSeries {
  std::vector<double> rate_dph;  // column - subtract, deg/h
  double dt_s = 0.0;             // (t_last - t_first) / (n - 1)
  std::string column, subtract;  // the recording's names of the columns read
  // The gyro's reference rate (ref_rate_dps, or the axis's) min and max in deg/h when the recording has it and
  // it is neither analysed nor subtracted (a rotating gyro's Allan deviation measures the motion); else 0, 0.
  double reference_min_dph = 0.0, reference_max_dph = 0.0;
};

// Errors name the file and line: a column that is not a rate or not there, a step that differs from the first
// by more than 1e-4 of it (`purpose` needs uniform sampling; nothing is resampled), fewer than two samples.
RateSeries read_rate_series(const std::filesystem::path& path, const RateSeriesRequest& request);

}  // namespace gyrosid
