// What a model file holds, whatever its kind: the calibration of one gyro (CalibrationModel: rbf, classical,
// greybox, hybrid, explained, or a kind registered from outside) or of a gyro triad (TriadModel, thesis
// eq 3.72). Every kind is one entry of model_kinds() (model_kinds.h), loaded by load_sensor_model(); the verbs
// that take any model file - compensate, export, cof - work through this interface, so none of them reads a
// file's kind itself.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/recording.h"

namespace gyrosid {

inline constexpr std::string_view kModelFormat = "gyrosid-model/1";

// A recording compensated by a model (model/compensate_recording.h).
struct CompensatedRecording {
  Recording recording;                   // the input plus the compensated columns
  std::optional<double> rms_before_dph;  // gyro - ref, when the reference is recorded everywhere
  std::optional<double> rms_after_dph;   // compensated - ref
  std::optional<double> coverage_95;     // |compensated - ref| <= 1.96 sigma, models with a posterior
  std::size_t samples = 0;               // rows compensated
  std::string added;                     // the columns added, e.g. "compensated_dps", "compensated_{x,y,z}_dps"
  std::string reference;                 // the reference columns the rms is taken against
};

class SensorModel {
 public:
  virtual ~SensorModel() = default;

  virtual std::string_view kind() const = 0;
  virtual int gyros() const = 0;  // 1, or 3 for a triad
  // The model file's JSON: format gyrosid-model/1, "kind", and the kind's values (loads back to the same numbers).
  virtual nlohmann::json to_json() const = 0;
  // Dependency-free C99 <prefix>.h and <prefix>.c in `dir`, written atomically.
  virtual void export_c(const std::filesystem::path& dir, const std::string& prefix) const = 0;
  // The recording with the compensated columns added (compensate_recording.h).
  virtual CompensatedRecording compensate_recording(Recording recording) const = 0;
  // The recording at `input` compensated into `output`, streamed where the kind can (compensate_recording.h).
  // `axis` (x, y or z) picks the gyro of a triad recording a single-gyro model applies to; a triad model
  // compensates all three and refuses it.
  virtual CompensatedRecording compensate_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                               const std::string& axis) const = 0;
};

// Saving and loading a model file of any kind, by its "kind" (model_kinds.h); Errors name the file. `extra`
// (training provenance, the solve's summary, a fit's sigmas) is stored beside the model's values.
void save_model(const std::filesystem::path& path, const SensorModel& model, const nlohmann::json& extra);
// The file save_model writes: the model's values, each top-level field of `extra` beside or over them.
nlohmann::json model_file_json(const SensorModel& model, const nlohmann::json& extra);
// The reverse: the top-level fields of a model file that are not the model's own values as it writes them
// (training, summary, a fit's sigmas), so that model_file_json(model, them) is the file again.
nlohmann::json fields_beside(const nlohmann::json& file, const SensorModel& model);
std::unique_ptr<SensorModel> sensor_model_from_json(const nlohmann::json& j, const std::string& source);
std::unique_ptr<SensorModel> load_sensor_model(const std::filesystem::path& path);
// A model file's JSON as it is (its training and summary included); Error naming the file it cannot read.
nlohmann::json load_model_json(const std::filesystem::path& path);

}  // namespace gyrosid
