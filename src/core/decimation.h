// Block means: a recording sampled faster than a command's model can use, reduced to the means of b
// consecutive samples.
//
// A gyro sample is already the mean rate over its interval, so the mean of b consecutive samples is the mean
// rate over b dt: the continuous-time noise processes (white, Gauss-Markov, random walk, flicker) are the same
// processes sampled at b dt; only their per-sample variances change (white: sigma^2 / b). What can change
// is the deterministic part where a model is nonlinear in an input that varies inside a block: the mean of
// f over a block differs from f at the block's mean inputs by about f'' var / 2. So the within-block spread
// of every input (the reference rate, the temperature) is kept per block and stated.
//
// A block never spans a gap in the sampling (a step over 1.5 nominal intervals, the nominal interval being
// the median step of the first 1000) or a change of position_id; the samples left over before a gap and at
// the end (fewer than b) are dropped and counted. A block's time is the mean of its samples' times. nan in
// an optional column makes its block's mean nan.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/recording.h"

namespace gyrosid {

// --decimate auto|none|<b>.
struct DecimationRequest {
  enum class Mode { automatic, none, factor };
  Mode mode = Mode::automatic;
  int factor = 1;                    // Mode::factor: b >= 1
  // automatic: the smallest b that leaves at most this many samples. explain costs about 0.5 ms a sample (a
  // 100-Hz thermal-cycle recording: 28 s at 50,000 block means of 27, 71 s at 96,000 of 14;
  // experiments/real_recordings/scale.py), so 50,000 keeps 10^6 samples within a minute.
  std::size_t target_rows = 50000;
  // "auto", "none" or a whole number >= 1; Error naming `option` otherwise.
  static DecimationRequest parse(const std::string& text, std::string_view option);
  int factor_for(std::size_t rows) const;
  std::string validate() const;
};

// How much an input varied inside the blocks.
struct InputSpread {
  std::string column;      // e.g. ref_rate_dps, temp_c
  double max_sd = 0.0;     // the largest within-block standard deviation, in the column's unit
  double max_range = 0.0;  // the largest within-block max - min
  std::vector<double> sd;  // per block
};

struct Decimation {
  int factor = 1;
  std::size_t rows_in = 0, rows_out = 0;
  std::size_t dropped = 0;  // samples in incomplete blocks (before a gap, at the end)
  std::size_t breaks = 0;   // gaps and position changes that ended a block early
  double interval_in_s = 0.0, interval_out_s = 0.0;  // nominal (median) sample intervals
  std::vector<InputSpread> inputs;
  bool applied() const { return factor > 1; }
  const InputSpread* spread(std::string_view column) const;
  // One sentence for the command's output: the factor, the intervals, the samples, each input's spread.
  std::string statement() const;
  nlohmann::json to_json() const;
};

// Block means of rows fed one at a time (a recording streamed from its file).
class BlockMeans {
 public:
  // `names`: the columns of each row (t_s among them); `inputs`: the columns whose spread is kept.
  BlockMeans(std::vector<std::string> names, int factor, const std::vector<std::string>& inputs);
  void add(const std::vector<double>& row);
  // The block means as a recording (source, metadata: the caller's) and what was done.
  Recording finish(const std::string& source, const std::vector<std::pair<std::string, std::string>>& metadata, Decimation& info);

 private:
  void start_rows();
  void feed(const std::vector<double>& row);
  void close_block(bool complete);

  std::vector<std::string> names_;
  int factor_;
  std::size_t t_col_ = 0;
  std::ptrdiff_t position_col_ = -1;
  std::vector<std::size_t> input_cols_;
  std::vector<std::vector<double>> pending_;  // the first rows, until the nominal interval is known
  double interval_ = 0.0;
  bool started_ = false;
  // The open block: its first row and the sums of each column's offsets from it (and of their squares, inputs).
  std::vector<double> first_, sum_, sum2_, lo_, hi_;
  double last_t_ = 0.0;
  int count_ = 0;
  std::vector<std::vector<double>> out_;
  Decimation info_;
};

struct DecimatedRecording {
  Recording recording;
  Decimation decimation;
};

// A recording file read with block means (automatic: its rows counted first). `columns`: keep only these
// (every column when empty); `inputs`: the columns whose within-block spread is stated. Factor 1 reads the
// file as read_recording does.
DecimatedRecording read_decimated(const std::filesystem::path& path, const DecimationRequest& request, const std::vector<std::string>& inputs,
                                  const std::vector<std::string>& columns = {});
// The same for a recording in memory.
DecimatedRecording decimate(const Recording& recording, const DecimationRequest& request, const std::vector<std::string>& inputs);

}  // namespace gyrosid
