#include "model/compensate_recording.h"

#include <algorithm>
#include <cmath>

#include "core/atomic_file.h"
#include "core/axis_view.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/recording_reader.h"
#include "core/units.h"

namespace gyrosid {

CompensatedRecording compensate_recording(const CalibrationModel& model, Recording recording) {
  const Dataset data = make_dataset(recording, model.features(), model.target());
  const Eigen::VectorXd comp = compensate(model, data);
  std::vector<double> dps(static_cast<std::size_t>(comp.size()));
  for (Eigen::Index i = 0; i < comp.size(); ++i) dps[static_cast<std::size_t>(i)] = units::radps_to_dps(comp(i));
  recording.set_column("compensated_dps", dps);
  Eigen::VectorXd sigma;
  if (model.posterior()) {
    sigma = model.predict_with_sigma(data.x).sigma;
    std::vector<double> s(static_cast<std::size_t>(sigma.size()));
    for (Eigen::Index i = 0; i < sigma.size(); ++i) s[static_cast<std::size_t>(i)] = units::radps_to_dps(sigma(i));
    recording.set_column("compensated_sigma_dps", s);
  }
  CompensatedRecording out{std::move(recording), std::nullopt, std::nullopt, std::nullopt, static_cast<std::size_t>(data.size()), "compensated_dps", "ref_rate_dps"};
  if (data.reference.allFinite()) {
    const double n = static_cast<double>(data.size());
    out.rms_before_dph = units::radps_to_dph(std::sqrt((data.measured - data.reference).squaredNorm() / n));
    out.rms_after_dph = units::radps_to_dph(std::sqrt((comp - data.reference).squaredNorm() / n));
    if (sigma.size() > 0) out.coverage_95 = ((comp - data.reference).array().abs() <= 1.96 * sigma.array()).cast<double>().mean();
  }
  return out;
}

CompensatedRecording TriadModel::compensate_recording(Recording recording) const {
  const TriadData data = make_triad_data(recording);
  const Eigen::MatrixX3d comp = compensate(data);
  for (int a = 0; a < 3; ++a) {
    std::vector<double> dps(static_cast<std::size_t>(comp.rows()));
    for (Eigen::Index k = 0; k < comp.rows(); ++k) dps[static_cast<std::size_t>(k)] = units::radps_to_dps(comp(k, a));
    recording.set_column(std::string("compensated_") + "xyz"[a] + "_dps", std::move(dps));
  }
  CompensatedRecording out{std::move(recording), std::nullopt, std::nullopt, std::nullopt, static_cast<std::size_t>(data.size()),
                           "compensated_{x,y,z}_dps", "ref_rate_{x,y,z}_dps"};
  if (data.has_reference()) {
    const double n = 3.0 * static_cast<double>(data.size());
    out.rms_before_dph = units::radps_to_dph(std::sqrt((data.gyro - data.reference).squaredNorm() / n));
    out.rms_after_dph = units::radps_to_dph(std::sqrt((comp - data.reference).squaredNorm() / n));
  }
  return out;
}

namespace {

// The single-gyro recording a model reads, from rows of a recording with columns `names`: the gyro's
// columns under the single-gyro names, and every other column the model takes as a feature.
class ModelColumns {
 public:
  ModelColumns(const CalibrationModel& model, const std::vector<std::string>& names, const GyroColumns& g, std::string source)
      : source_(std::move(source)) {
    const auto add = [&](const std::string& column, const std::string& as) {
      const auto it = std::find(names.begin(), names.end(), column);
      if (it != names.end()) picks_.push_back({static_cast<std::size_t>(it - names.begin()), as});
    };
    add("t_s", "t_s"), add(g.gyro, "gyro_dps"), add(g.ref, "ref_rate_dps");
    if (!g.temp.empty()) add(g.temp, "temp_c");
    for (const auto& f : model.features()) {
      if (f != "measured_rate" && f != "temperature" && f != "temperature_rate") add(f, f);
    }
  }
  // Rows [begin, end) of a row-major block as a recording.
  Recording recording(const std::vector<double>& rows, std::size_t width, std::size_t count) const {
    Recording rec(source_);
    for (const auto& [index, name] : picks_) {
      std::vector<double> values(count);
      for (std::size_t r = 0; r < count; ++r) values[r] = rows[r * width + index];
      rec.set_column(name, std::move(values));
    }
    return rec;
  }
  std::vector<std::string> columns(const std::vector<std::string>& names) const {
    std::vector<std::string> out;
    for (const auto& [index, name] : picks_) out.push_back(names[index]);
    return out;
  }

 private:
  std::string source_;
  std::vector<std::pair<std::size_t, std::string>> picks_;
};

// Sums over the samples for the rms errors and the band's coverage.
struct CompensationSums {
  double before = 0.0, after = 0.0, covered = 0.0, n = 0.0;
  void add(const Dataset& d, const Eigen::VectorXd& comp, const Eigen::VectorXd& sigma) {
    before += (d.measured - d.reference).squaredNorm(), after += (comp - d.reference).squaredNorm();
    if (sigma.size() > 0) covered += ((comp - d.reference).array().abs() <= 1.96 * sigma.array()).cast<double>().sum();
    n += static_cast<double>(d.size());
  }
};

// The output's columns: the input's, then compensated<suffix> and, for a model with a posterior,
// compensated_sigma<suffix> - in place where the input has them already.
struct OutputColumns {
  std::vector<std::string> names;
  std::size_t comp = 0, sigma = 0;
  bool with_sigma = false;

  OutputColumns(std::vector<std::string> input, const std::string& suffix, bool posterior) : names(std::move(input)), with_sigma(posterior) {
    comp = index("compensated" + suffix);
    if (with_sigma) sigma = index("compensated_sigma" + suffix);
  }
  std::size_t index(const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
    names.push_back(name);
    return names.size() - 1;
  }
};

// `count` rows of a row-major block of `width` input columns as recording text, the compensated rate and its
// sigma (rad/s) written in their columns in deg/s.
void append_compensated_rows(const std::vector<double>& rows, std::size_t width, std::size_t count, const Eigen::VectorXd& comp,
                             const Eigen::VectorXd& sigma, const OutputColumns& cols, std::string& text) {
  std::vector<double> values(cols.names.size());
  for (std::size_t r = 0; r < count; ++r) {
    std::copy(rows.begin() + static_cast<std::ptrdiff_t>(r * width), rows.begin() + static_cast<std::ptrdiff_t>((r + 1) * width), values.begin());
    values[cols.comp] = units::radps_to_dps(comp(static_cast<Eigen::Index>(r)));
    if (cols.with_sigma) values[cols.sigma] = units::radps_to_dps(sigma(static_cast<Eigen::Index>(r)));
    for (std::size_t c = 0; c < values.size(); ++c) (text += c ? "," : "") += format_number(values[c]);
    text += '\n';
  }
}

// The compensated rate (and its sigma, models with a posterior) of a dataset, deg/s.
void compensate_dataset(const CalibrationModel& model, const Dataset& d, Eigen::VectorXd& comp, Eigen::VectorXd& sigma) {
  comp = compensate(model, d);
  sigma = model.posterior() ? model.predict_with_sigma(d.x).sigma : Eigen::VectorXd();
}

}  // namespace

CompensatedRecording compensate_file(const CalibrationModel& model, const std::filesystem::path& input, const std::filesystem::path& output,
                                     const std::string& axis, std::size_t chunk_rows) {
  RecordingReader reader(input);
  const GyroColumns g = gyro_columns(reader.names(), axis, reader.source());
  const ModelColumns picks(model, reader.names(), g, reader.source());
  const OutputColumns cols(reader.names(), g.axis.empty() ? "_dps" : "_" + g.axis + "_dps", model.posterior() != nullptr);
  const bool pointwise = model.pointwise() && std::find(model.features().begin(), model.features().end(), "temperature_rate") == model.features().end();
  Eigen::VectorXd whole_comp, whole_sigma;  // a model with dynamics: run over the whole recording first
  if (!pointwise) {
    const Dataset d = make_dataset(single_axis_view(read_recording(input, picks.columns(reader.names())), axis), model.features(), model.target());
    compensate_dataset(model, d, whole_comp, whole_sigma);
  }
  CompensationSums sums;
  Recording header(reader.source());
  for (const auto& [key, value] : reader.metadata()) header.set_meta(key, value);
  for (const auto& name : cols.names) header.set_column(name, {});
  Progress progress("compensating " + reader.source(), std::max<std::size_t>(reader.total_bytes(), 1));
  write_file_atomic(output, [&](std::ostream& out) {
    std::string text = format_recording(header);
    const std::size_t width = reader.names().size();
    std::vector<double> rows, row;
    for (bool more = true; more;) {
      rows.clear();
      std::size_t count = 0;
      while (count < chunk_rows && (more = reader.next(row))) rows.insert(rows.end(), row.begin(), row.end()), ++count;
      if (count == 0) break;
      const std::size_t first = reader.rows() - count;
      const Dataset d = make_dataset(picks.recording(rows, width, count), model.features(), model.target());
      Eigen::VectorXd comp, sigma;
      if (pointwise) compensate_dataset(model, d, comp, sigma);
      else comp = whole_comp.segment(first, count), sigma = whole_sigma.size() ? Eigen::VectorXd(whole_sigma.segment(first, count)) : Eigen::VectorXd();
      sums.add(d, comp, sigma);
      append_compensated_rows(rows, width, count, comp, sigma, cols, text);
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
      progress.update(reader.bytes_read());
    }
  });
  progress.finish();
  CompensatedRecording result{std::move(header), std::nullopt, std::nullopt, std::nullopt, reader.rows(),
                              g.axis.empty() ? "compensated_dps" : "compensated_" + g.axis + "_dps", "ref_rate_dps"};
  result.rms_before_dph = units::radps_to_dph(std::sqrt(sums.before / sums.n));
  result.rms_after_dph = units::radps_to_dph(std::sqrt(sums.after / sums.n));
  if (model.posterior()) result.coverage_95 = sums.covered / sums.n;
  return result;
}

CompensatedRecording CalibrationModel::compensate_recording(Recording recording) const {
  return gyrosid::compensate_recording(*this, std::move(recording));
}

CompensatedRecording CalibrationModel::compensate_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                                     const std::string& axis) const {
  return gyrosid::compensate_file(*this, input, output, axis);
}

CompensatedRecording TriadModel::compensate_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                                 const std::string& axis) const {
  if (!axis.empty()) fail("--axis applies to a single-gyro model; a triad model compensates all three gyros");
  CompensatedRecording r = compensate_recording(read_recording(input));
  write_recording(r.recording, output);
  return r;
}

}  // namespace gyrosid
