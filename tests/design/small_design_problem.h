// The design tests' shared fixtures: the reference sensor, the short and medium flights' envelope, and a
// small design problem over them.
#pragma once

#include <memory>

#include "design/design.h"
#include "sensor/sensor_config.h"

namespace gyrosid::design::fixtures {

inline const SensorSpec& reference_sensor() {
  static const SensorSpec s = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  return s;
}

inline std::shared_ptr<const Envelope> short_and_medium() {
  static const auto e = [] {
    EnvelopeOptions o;
    o.flights = {"short", "medium"};
    return std::make_shared<const Envelope>(load_envelope(o, as_triad(reference_sensor())));
  }();
  return e;
}

// A small design problem (classical model, short and medium flights, 20 min in 3 segments).
struct SmallProblem {
  SmallProblem(ModelFamily family = ModelFamily::classical, Criterion criterion = Criterion::cof, ModelOptions model = {},
               const SensorSpec& sensor = reference_sensor())
      : space([] {
          DesignSpaceOptions o;
          o.budget_min = 20;
          o.segments = 3;
          o.rate_hz = 1;
          return o;
        }(), short_and_medium()->domain.temp_min_c, short_and_medium()->domain.temp_max_c, short_and_medium()->domain.rate_max_radps),
        context(sensor, short_and_medium(), family, model, criterion, model_domain(space)),
        problem(context, space, QuadratureOptions{}) {}
  DesignSpace space;
  DesignContext context;
  DesignProblem problem;
};

}  // namespace gyrosid::design::fixtures
