// Every model kind, in one registry: its name (the "kind" of a model file), a one-line summary and its
// loader from the model file's JSON - the single-gyro kinds and the triad alike (sensor_model.h). A new kind
// is one entry in model_kinds() (model_kinds.cpp); its fitter registers beside the others in
// solvers/calibrate.cpp. tests/model/toy_model_kind.cpp adds a kind and its fitter from outside the library
// (solvers/calibrate.h register_model_kind).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "core/registry.h"
#include "model/calibration_model.h"
#include "model/sensor_model.h"

namespace gyrosid {

// What a loader receives: the model file's JSON, and for a single-gyro kind its common fields and its
// kind-specific "parameters".
struct ModelFile {
  const nlohmann::json& json;  // the whole file
  const std::string& source;   // file name, for messages

  const nlohmann::json& parameters() const { return json.at("parameters"); }
  std::vector<std::string> features() const { return json.at("features").get<std::vector<std::string>>(); }
  ModelTarget target() const;
};

using ModelKindRegistry = Registry<SensorModel, const ModelFile&>;
const ModelKindRegistry& model_kinds();
// The same registry, open for a program to add its own kinds before it loads any model (not thread-safe:
// register at start-up).
ModelKindRegistry& extend_model_kinds();

}  // namespace gyrosid
