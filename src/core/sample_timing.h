// Sample times: an imported stream's, exact and in bounded memory; and the uniform-sampling rule (UniformStepCheck).
//
// Exact times: a log's integer stamps (ns or us) less the first are written as decimal seconds by integer
// arithmetic, so 30 ms is "0.03", never "0.030000000000000002" (the double nearest 0.03 is what a reader gets).
//
// The sampling: every step between consecutive stamps goes into a histogram of at most `max_bins` distinct
// values. While the steps take fewer values than that (real logs: a few hundred), the median and every
// statistic below are exact; beyond it the bins are merged in pairs (the bin width doubles) as often as needed,
// and the statistics hold to the bin width. A stream is uniform when every step is within 1e-4 of the median
// step (relative), the tolerance of UniformStepCheck below.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>

namespace gyrosid {

// ticks / ticks_per_second as a decimal ("0.03", "-1.5", "12"); ticks_per_second a power of ten (1 .. 1e18).
std::string ticks_to_seconds_text(std::int64_t ticks, std::int64_t ticks_per_second);
void append_ticks_as_seconds(std::string& out, std::int64_t ticks, std::int64_t ticks_per_second);

class StepHistogram {
 public:
  explicit StepHistogram(std::size_t max_bins = std::size_t{1} << 16) : max_bins_(max_bins) {}
  void add(std::int64_t step);  // step > 0, in ticks

  std::uint64_t count() const { return count_; }
  std::int64_t min() const { return min_; }
  std::int64_t max() const { return max_; }
  std::int64_t bin_width() const { return width_; }
  // The step at index count / 2 of the sorted steps (core/recording.h's median_sample_interval), in ticks: exact
  // while the bin width is 1, else the centre of its bin.
  double median() const;
  // Steps farther than `relative_tolerance * centre` from `centre`, and the rms of (step - centre), in ticks.
  std::uint64_t count_outside(double centre, double relative_tolerance) const;
  double rms_deviation(double centre) const;

 private:
  double centre_of(std::int64_t key) const;
  std::size_t max_bins_;
  std::map<std::int64_t, std::uint64_t> bins_;  // step / width -> count
  std::int64_t width_ = 1;
  std::uint64_t count_ = 0;
  std::int64_t min_ = 0, max_ = 0;
};

inline constexpr double kUniformStepTolerance = 1e-4;

// The rule of every computation that needs one sample interval (the Allan deviation, a recording's noise): each
// step within kUniformStepTolerance of the first (relative); nothing is resampled. The times are fed in order,
// from memory (uniform_sample_interval, core/recording.h) or streamed (read_rate_series, core/rate_series.h).
class UniformStepCheck {
 public:
  explicit UniformStepCheck(std::string purpose) : purpose_(std::move(purpose)) {}
  // Takes the next time. Returns "" while the rule holds, else the error for this sample (the caller prefixes
  // its file and line): "<purpose> needs uniform sampling, but the step here is ...".
  std::string add(double t_s);
  // The mean interval (last - first) / (samples - 1). Error naming `source` with fewer than two samples.
  double interval(std::string_view source) const;

 private:
  std::string purpose_;
  std::size_t count_ = 0;
  double first_ = 0.0, last_ = 0.0, step_ = 0.0;
};

struct SamplingSummary {
  double rate_hz = 0.0;        // 1 / the median step (0 with fewer than two samples)
  bool uniform = true;
  std::string description;     // for the recording's metadata `sampling`
};

SamplingSummary summarize_sampling(const StepHistogram& steps, std::int64_t ticks_per_second);

// A duration for people: "5 ms", "2.5 us", "1.2 s" (4 significant digits).
std::string human_duration(double seconds);

}  // namespace gyrosid
