#include "core/sample_timing.h"

#include <cmath>

#include "core/error.h"
#include "core/format.h"

namespace gyrosid {

namespace {

int decimal_digits(std::int64_t ticks_per_second) {
  int digits = 0;
  for (std::int64_t p = 1; p < ticks_per_second; p *= 10) ++digits;
  std::int64_t check = 1;
  for (int i = 0; i < digits; ++i) check *= 10;
  if (ticks_per_second < 1 || check != ticks_per_second || digits > 18) fail("ticks per second must be a power of ten, not ", ticks_per_second);
  return digits;
}

}  // namespace

void append_ticks_as_seconds(std::string& out, std::int64_t ticks, std::int64_t ticks_per_second) {
  const int digits = decimal_digits(ticks_per_second);
  // |ticks| as unsigned, so the most negative stamp is exact too.
  const std::uint64_t magnitude = ticks < 0 ? ~static_cast<std::uint64_t>(ticks) + 1 : static_cast<std::uint64_t>(ticks);
  const auto tps = static_cast<std::uint64_t>(ticks_per_second);
  if (ticks < 0) out += '-';
  out += std::to_string(magnitude / tps);
  std::uint64_t fraction = magnitude % tps;
  if (fraction == 0) return;
  int width = digits;
  while (fraction % 10 == 0) fraction /= 10, --width;  // no trailing zeros
  const std::string text = std::to_string(fraction);
  out += '.';
  out.append(static_cast<std::size_t>(width) - text.size(), '0');
  out += text;
}

std::string ticks_to_seconds_text(std::int64_t ticks, std::int64_t ticks_per_second) {
  std::string out;
  append_ticks_as_seconds(out, ticks, ticks_per_second);
  return out;
}

void StepHistogram::add(std::int64_t step) {
  if (count_ == 0 || step < min_) min_ = step;
  if (count_ == 0 || step > max_) max_ = step;
  ++count_;
  ++bins_[step / width_];
  while (bins_.size() > max_bins_) {  // merge bins in pairs: the width doubles
    std::map<std::int64_t, std::uint64_t> merged;
    for (const auto& [key, n] : bins_) merged[key / 2] += n;
    bins_ = std::move(merged);
    width_ *= 2;
  }
}

double StepHistogram::centre_of(std::int64_t key) const {
  return static_cast<double>(key) * static_cast<double>(width_) + 0.5 * static_cast<double>(width_ - 1);
}

double StepHistogram::median() const {
  if (count_ == 0) return 0.0;
  const std::uint64_t target = count_ / 2;  // 0-based index in the sorted steps
  std::uint64_t seen = 0;
  for (const auto& [key, n] : bins_) {
    seen += n;
    if (seen > target) return centre_of(key);
  }
  return centre_of(bins_.rbegin()->first);
}

std::uint64_t StepHistogram::count_outside(double centre, double relative_tolerance) const {
  std::uint64_t n = 0;
  for (const auto& [key, c] : bins_) {
    if (std::abs(centre_of(key) - centre) > relative_tolerance * centre) n += c;
  }
  return n;
}

double StepHistogram::rms_deviation(double centre) const {
  if (count_ == 0) return 0.0;
  double sum = 0.0;
  for (const auto& [key, c] : bins_) {
    const double d = centre_of(key) - centre;
    sum += static_cast<double>(c) * d * d;
  }
  return std::sqrt(sum / static_cast<double>(count_));
}

std::string human_duration(double seconds) {
  const double a = std::abs(seconds);
  if (a != 0.0 && a < 1e-3) return format_significant(seconds * 1e6, 4) + " us";
  if (a != 0.0 && a < 1.0) return format_significant(seconds * 1e3, 4) + " ms";
  return format_significant(seconds, 4) + " s";
}

SamplingSummary summarize_sampling(const StepHistogram& steps, std::int64_t ticks_per_second) {
  SamplingSummary s;
  if (steps.count() == 0) {
    s.description = "one sample: no sampling interval";
    return s;
  }
  const double tps = static_cast<double>(ticks_per_second);
  const double median = steps.median();
  s.rate_hz = tps / median;
  const std::uint64_t off = steps.count_outside(median, kUniformStepTolerance);
  s.uniform = off == 0;
  const std::string exact = steps.bin_width() == 1 ? "" : str_cat(" (to ", human_duration(static_cast<double>(steps.bin_width()) / tps), ")");
  if (s.uniform) {
    s.description = str_cat("uniform: every step within ", format_significant(kUniformStepTolerance * 100.0, 2), " % of the median ",
                            human_duration(median / tps), exact, " (", steps.count(), " steps)");
  } else {
    s.description = str_cat("not uniform: ", off, " of ", steps.count(), " steps differ from the median ", human_duration(median / tps), exact,
                            " by more than ", format_significant(kUniformStepTolerance * 100.0, 2), " %; steps from ",
                            human_duration(static_cast<double>(steps.min()) / tps), " to ", human_duration(static_cast<double>(steps.max()) / tps),
                            ", rms jitter about the median ", human_duration(steps.rms_deviation(median) / tps));
  }
  return s;
}

std::string UniformStepCheck::add(double t_s) {
  ++count_;
  if (count_ == 1) first_ = t_s;
  if (count_ == 2) step_ = t_s - first_;
  const double step = t_s - last_;
  last_ = t_s;
  if (count_ <= 2 || std::abs(step - step_) <= kUniformStepTolerance * step_) return "";
  return str_cat(purpose_, " needs uniform sampling, but the step here is ", format_number(step), " s after steps of ", format_number(step_),
                 " s (gyrosid does not resample silently; resample the recording first)");
}

double UniformStepCheck::interval(std::string_view source) const {
  if (count_ < 2) fail(source, ": ", purpose_, " needs at least two samples");
  return (last_ - first_) / static_cast<double>(count_ - 1);
}

}  // namespace gyrosid
