#include "fuzz_targets.h"

#include <nlohmann/json.hpp>

#include "core/config.h"
#include "core/error.h"
#include "core/recording.h"
#include "model/calibration_model.h"
#include "sensor/sensor_config.h"
#include "solvers/calibrate.h"
#include "trajectory/flight.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid::fuzz {

namespace {

ConfigNode yaml(std::string_view input) { return ConfigNode::parse(std::string(input), "fuzz.yaml"); }

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"recording", {"tests/fuzz/seeds/recording/*"}, [](std::string_view in) { parse_recording(in, "fuzz.csv"); }},
      {"sensor_config", {"configs/sensors/*.yaml", "experiments/*/sensor*.yaml"}, [](std::string_view in) { load_sensor(yaml(in)); }},
      {"trajectory_config", {"configs/trajectories/*.yaml"}, [](std::string_view in) { load_trajectory(yaml(in)); }},
      {"calibration_config", {"configs/calibration/*.yaml"},
       [](std::string_view in) {
         // The request, and the model fitter it names (whose options are then validated).
         model_fitters().make(calibration_request_from_config(yaml(in)).model, calibration_request_from_config(yaml(in)));
       }},
      {"flight_config", {"tests/fuzz/seeds/flight_config/*"}, [](std::string_view in) { load_flight_profile(yaml(in)); }},
      {"model_json", {"tests/fuzz/seeds/model_json/*"},
       [](std::string_view in) {
         nlohmann::json j;
         try {
           j = nlohmann::json::parse(in);
         } catch (const nlohmann::json::exception&) {
           return;  // not JSON at all: load_model reports it; here only parsed documents reach the loader
         }
         model_from_json(j, "fuzz.json");
       }},
      {"flight_csv", {"tests/fuzz/seeds/flight_csv/*"}, [](std::string_view in) { parse_flight_csv(std::string(in), "fuzz.csv"); }},
  };
  return all;
}

const Target& target(std::string_view name) {
  for (const auto& t : targets()) {
    if (t.name == name) return t;
  }
  fail("unknown fuzz target '", name, "'");
}

void run_one(const Target& t, std::string_view input) {
  try {
    t.run(input);
  } catch (const Error&) {
    // refused with a message: what a reader should do with bad input
  }
}

}  // namespace gyrosid::fuzz
