#include "model/sensor_model.h"

#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "model/model_kinds.h"

namespace gyrosid {

void save_model(const std::filesystem::path& path, const SensorModel& model, const nlohmann::json& extra) {
  write_file_atomic(path, model_file_json(model, extra).dump(1) + "\n");
}

nlohmann::json model_file_json(const SensorModel& model, const nlohmann::json& extra) {
  nlohmann::json j = model.to_json();
  for (auto it = extra.begin(); it != extra.end(); ++it) j[it.key()] = it.value();
  return j;
}

nlohmann::json fields_beside(const nlohmann::json& file, const SensorModel& model) {
  const nlohmann::json values = model.to_json();
  nlohmann::json extra = nlohmann::json::object();
  for (auto it = file.begin(); it != file.end(); ++it) {
    if (!values.contains(it.key()) || values.at(it.key()) != it.value()) extra[it.key()] = it.value();
  }
  return extra;
}

std::unique_ptr<SensorModel> sensor_model_from_json(const nlohmann::json& j, const std::string& source) {
  try {
    if (j.value("format", "") != kModelFormat) {
      fail(source, ": not a gyrosid model (expected \"format\": \"", kModelFormat, "\")");
    }
    return model_kinds().make(j.at("kind").get<std::string>(), ModelFile{j, source});
  } catch (const nlohmann::json::exception& e) {
    fail(source, ": malformed model: ", e.what());
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.rfind(source, 0) == 0) throw;
    fail(source, ": ", what);
  }
}

std::unique_ptr<SensorModel> load_sensor_model(const std::filesystem::path& path) { return sensor_model_from_json(load_model_json(path), path.string()); }

nlohmann::json load_model_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) fail(path.string(), ": cannot open model");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    fail(path.string(), ": not valid JSON: ", e.what());
  }
  return j;
}

}  // namespace gyrosid
