#include "pipeline/surface_job.h"

#include "core/error.h"
#include "core/format.h"
#include "sensor/error_surface.h"
#include "sensor/sensor_config.h"

namespace gyrosid {

std::string SurfaceJobInput::validate() const {
  if (model.empty()) return "--model is required";
  if (points) {
    for (int n : *points) {
      if (n < 2 || n > 10000) return str_cat("--points: expected whole numbers from 2 to 10000, found ", n);
    }
  }
  return "";
}

SurfaceJobResult run_surface_job(const SurfaceJobInput& in) {
  if (const std::string p = in.validate(); !p.empty()) fail(p);
  SurfaceJobResult r;
  const nlohmann::json model_json = load_model_json(in.model);  // one read: the model and its training domain
  r.model = model_from_json(model_json, in.model);
  const SensorSpec spec = load_sensor_file(in.sensor);
  const GyroSensor& truth = representative_gyro(spec);
  // The options where given, else the temperatures the model was trained on (within the sensor's surface
  // grid) and the thesis's rates.
  r.grid = comparison_grid(truth, {model_json.value("training", nlohmann::json::object())});
  if (in.temp_range_c) r.grid.temp_min_c = (*in.temp_range_c)[0], r.grid.temp_max_c = (*in.temp_range_c)[1];
  if (in.rate_range_dps) r.grid.rate_min_dps = (*in.rate_range_dps)[0], r.grid.rate_max_dps = (*in.rate_range_dps)[1];
  if (in.points) r.grid.temp_points = (*in.points)[0], r.grid.rate_points = (*in.points)[1];
  r.comparison = compare_surfaces(*r.model, truth, r.grid);
  return r;
}

}  // namespace gyrosid
