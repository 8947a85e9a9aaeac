#include "core/decimation.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/recording_reader.h"

namespace gyrosid {
namespace {

constexpr std::size_t kIntervalRows = 1000;  // steps whose median is the nominal interval
constexpr double kGap = 1.5;                 // a step over this many nominal intervals is a gap

// The unit of a column from its suffix, as the format names them.
std::string unit_of(const std::string& column) {
  for (const auto& [suffix, unit] : {std::pair{"_dps", "deg/s"}, {"_dph", "deg/h"}, {"_c", "C"}, {"_s", "s"}, {"_mps2", "m/s^2"}}) {
    if (column.size() > std::string_view(suffix).size() && column.ends_with(suffix)) return unit;
  }
  return "";
}

double median_step(const std::vector<std::vector<double>>& rows, std::size_t t_col) {
  std::vector<double> t;
  for (const auto& r : rows) t.push_back(r[t_col]);
  return median_sample_interval(t);
}

}  // namespace

DecimationRequest DecimationRequest::parse(const std::string& text, std::string_view option) {
  DecimationRequest r;
  if (text == "auto") return r;
  if (text == "none") {
    r.mode = Mode::none;
    return r;
  }
  int b = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), b);
  if (ec != std::errc() || end != text.data() + text.size() || b < 1) {
    fail(option, ": '", text, "' is not auto, none or a whole number of samples per block (>= 1)");
  }
  r.mode = Mode::factor, r.factor = b;
  return r;
}

std::string DecimationRequest::validate() const {
  if (mode == Mode::factor && factor < 1) return str_cat("decimation factor ", factor, " must be at least 1");
  if (mode == Mode::automatic && target_rows < 100) return str_cat("decimation target ", target_rows, " samples must be at least 100");
  return "";
}

int DecimationRequest::factor_for(std::size_t rows) const {
  if (mode == Mode::none) return 1;
  if (mode == Mode::factor) return factor;
  return static_cast<int>(std::max<std::size_t>(1, (rows + target_rows - 1) / target_rows));
}

const InputSpread* Decimation::spread(std::string_view column) const {
  for (const auto& s : inputs)
    if (s.column == column) return &s;
  return nullptr;
}

std::string Decimation::statement() const {
  std::string out = str_cat("decimated: block means of ", factor, " samples, interval ", format_significant(interval_in_s, 4), " -> ",
                            format_significant(interval_out_s, 4), " s, ", rows_in, " -> ", rows_out, " samples");
  if (dropped > 0) out += str_cat(" (", dropped, " in incomplete blocks before ", breaks, " gap(s) and at the end left out)");
  std::vector<std::string> spreads;
  for (const auto& s : inputs) {
    const std::string unit = unit_of(s.column);
    spreads.push_back(str_cat(s.column, " ", format_significant(s.max_sd, 3), unit.empty() ? "" : " ", unit, " (range ",
                              format_significant(s.max_range, 3), ")"));
  }
  if (!spreads.empty()) out += "; largest within-block sd: " + join(spreads, ", ");
  return out;
}

nlohmann::json Decimation::to_json() const {
  nlohmann::json j = {{"factor", factor},       {"samples_in", rows_in},          {"samples_out", rows_out},
                      {"dropped", dropped},     {"breaks", breaks},               {"interval_in_s", interval_in_s},
                      {"interval_out_s", interval_out_s}};
  nlohmann::json spread = nlohmann::json::object();
  for (const auto& s : inputs) spread[s.column] = {{"max_sd", s.max_sd}, {"max_range", s.max_range}, {"unit", unit_of(s.column)}};
  j["within_block"] = spread;
  return j;
}

BlockMeans::BlockMeans(std::vector<std::string> names, int factor, const std::vector<std::string>& inputs)
    : names_(std::move(names)), factor_(factor) {
  if (factor_ < 1) fail("block means: factor ", factor_, " must be at least 1");
  const auto index = [&](std::string_view name) -> std::ptrdiff_t {
    const auto it = std::find(names_.begin(), names_.end(), name);
    return it == names_.end() ? -1 : it - names_.begin();
  };
  if (index("t_s") < 0) fail("block means: no column 't_s'");
  t_col_ = static_cast<std::size_t>(index("t_s"));
  position_col_ = index("position_id");
  for (const auto& name : inputs) {
    if (index(name) < 0) continue;
    input_cols_.push_back(static_cast<std::size_t>(index(name)));
    info_.inputs.push_back({name, 0.0, 0.0, {}});
  }
  const std::size_t n = names_.size();
  first_.resize(n), sum_.resize(n), sum2_.resize(n), lo_.resize(n), hi_.resize(n);
  out_.resize(n);
  info_.factor = factor_;
}

void BlockMeans::add(const std::vector<double>& row) {
  ++info_.rows_in;
  if (started_) return feed(row);
  pending_.push_back(row);
  if (pending_.size() > kIntervalRows) start_rows();
}

// The nominal interval from the rows held back, then those rows.
void BlockMeans::start_rows() {
  started_ = true;
  interval_ = median_step(pending_, t_col_);
  for (const auto& r : pending_) feed(r);
  pending_.clear();
  pending_.shrink_to_fit();
}

void BlockMeans::feed(const std::vector<double>& row) {
  const bool gap = count_ > 0 && row[t_col_] - last_t_ > kGap * interval_;
  const bool moved = count_ > 0 && position_col_ >= 0 && row[static_cast<std::size_t>(position_col_)] != first_[static_cast<std::size_t>(position_col_)];
  if (gap || moved) {
    ++info_.breaks;
    close_block(false);
  }
  if (count_ == 0) {
    first_ = row;
    std::fill(sum_.begin(), sum_.end(), 0.0), std::fill(sum2_.begin(), sum2_.end(), 0.0);
    lo_ = row, hi_ = row;
  }
  for (std::size_t c = 0; c < row.size(); ++c) {
    const double d = row[c] - first_[c];
    sum_[c] += d;
    sum2_[c] += d * d;
    lo_[c] = std::min(lo_[c], row[c]), hi_[c] = std::max(hi_[c], row[c]);
  }
  last_t_ = row[t_col_];
  if (++count_ == factor_) close_block(true);
}

void BlockMeans::close_block(bool complete) {
  if (!complete) {
    info_.dropped += static_cast<std::size_t>(count_);
    count_ = 0;
    return;
  }
  const double b = static_cast<double>(count_);
  for (std::size_t c = 0; c < out_.size(); ++c) out_[c].push_back(first_[c] + sum_[c] / b);
  for (std::size_t k = 0; k < input_cols_.size(); ++k) {
    const std::size_t c = input_cols_[k];
    const double mean = sum_[c] / b;
    const double sd = std::sqrt(std::max(0.0, sum2_[c] / b - mean * mean));
    InputSpread& s = info_.inputs[k];
    s.sd.push_back(sd);
    if (std::isfinite(sd)) s.max_sd = std::max(s.max_sd, sd), s.max_range = std::max(s.max_range, hi_[c] - lo_[c]);
  }
  count_ = 0;
}

Recording BlockMeans::finish(const std::string& source, const std::vector<std::pair<std::string, std::string>>& metadata, Decimation& info) {
  if (!started_) start_rows();
  close_block(count_ == factor_);
  Recording rec(factor_ > 1 ? str_cat(source, " (block means of ", factor_, ")") : source);
  for (const auto& [key, value] : metadata) rec.set_meta(key, value);
  for (std::size_t c = 0; c < names_.size(); ++c) rec.set_column(names_[c], std::move(out_[c]));
  info_.rows_out = rec.rows();
  info_.interval_in_s = interval_;
  info_.interval_out_s = rec.rows() > 1 ? median_sample_interval(rec.column("t_s")) : interval_ * factor_;
  if (rec.rows() == 0) fail(source, ": no block of ", factor_, " samples without a gap (", info_.rows_in, " samples)");
  if (factor_ > 1 && rec.meta("sample_rate_hz")) rec.set_meta("sample_rate_hz", format_number(1.0 / info_.interval_out_s));
  info = std::move(info_);
  return rec;
}

DecimatedRecording read_decimated(const std::filesystem::path& path, const DecimationRequest& request, const std::vector<std::string>& inputs,
                                  const std::vector<std::string>& columns) {
  if (auto p = request.validate(); !p.empty()) fail("--decimate: ", p);
  const int factor = request.mode == DecimationRequest::Mode::automatic ? request.factor_for(count_recording_rows(path)) : request.factor_for(0);
  RecordingReader reader(path);
  DecimatedRecording out;
  if (factor == 1) {
    out.recording = read_recording(reader, columns);
    out.decimation.rows_in = out.decimation.rows_out = out.recording.rows();
    out.decimation.interval_in_s = out.decimation.interval_out_s = median_sample_interval(out.recording.column("t_s"));
    return out;
  }
  std::vector<std::size_t> keep;
  std::vector<std::string> names;
  for (std::size_t c = 0; c < reader.names().size(); ++c) {
    if (!columns.empty() && std::find(columns.begin(), columns.end(), reader.names()[c]) == columns.end() && reader.names()[c] != "t_s") continue;
    keep.push_back(c), names.push_back(reader.names()[c]);
  }
  BlockMeans means(names, factor, inputs);
  Progress progress(str_cat("reading ", reader.source(), " (block means of ", factor, ")"), std::max<std::size_t>(reader.total_bytes(), 1));
  std::vector<double> row, kept(keep.size());
  while (reader.next(row)) {
    for (std::size_t k = 0; k < keep.size(); ++k) kept[k] = row[keep[k]];
    means.add(kept);
    if ((reader.rows() & 0xffff) == 0) progress.update(reader.bytes_read());
  }
  progress.finish();
  out.recording = means.finish(reader.source(), reader.metadata(), out.decimation);
  return out;
}

DecimatedRecording decimate(const Recording& recording, const DecimationRequest& request, const std::vector<std::string>& inputs) {
  if (auto p = request.validate(); !p.empty()) fail("--decimate: ", p);
  const int factor = request.factor_for(recording.rows());
  DecimatedRecording out;
  if (factor == 1) {
    out.recording = recording;
    out.decimation.rows_in = out.decimation.rows_out = recording.rows();
    out.decimation.interval_in_s = out.decimation.interval_out_s = median_sample_interval(recording.column("t_s"));
    return out;
  }
  BlockMeans means(recording.names(), factor, inputs);
  std::vector<const std::vector<double>*> cols;
  for (const auto& name : recording.names()) cols.push_back(&recording.column(name));
  std::vector<double> row(cols.size());
  for (std::size_t r = 0; r < recording.rows(); ++r) {
    for (std::size_t c = 0; c < cols.size(); ++c) row[c] = (*cols[c])[r];
    means.add(row);
  }
  out.recording = means.finish(recording.source(), recording.metadata(), out.decimation);
  return out;
}

}  // namespace gyrosid
