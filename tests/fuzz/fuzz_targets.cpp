#include "fuzz_targets.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <unistd.h>

#include "core/config.h"
#include "core/error.h"
#include "core/imu_import.h"
#include "core/imu_text_logs.h"
#include "core/recording.h"
#include "core/rosbag_imu.h"
#include "core/ulog_reader.h"
#include "model/calibration_model.h"
#include "sensor/sensor_config.h"
#include "solvers/calibrate.h"
#include "trajectory/flight.h"
#include "trajectory/trajectory_config.h"

namespace gyrosid::fuzz {

namespace {

ConfigNode yaml(std::string_view input) { return ConfigNode::parse(std::string(input), "fuzz.yaml"); }

// An importer's reader over the bytes, through the whole import (core/imu_import.h) into a stream that keeps
// nothing: the reader, the time and value checks, the sampling statistics and the metadata.
void import_bytes(ImuLogFormat format, std::string_view input) {
  std::istringstream in{std::string(input)};
  ImuImportOptions o;
  o.format = format;
  o.input = "fuzz.log";
  o.stationary = true;
  // A ULog import is also fuzzed without a given temperature (the log's own): for inputs of even length.
  if (format != ImuLogFormat::ulog || input.size() % 2 == 1) o.temp_c = 20.0;
  o.gyro_scale_dps_per_count = 0.01;
  std::unique_ptr<ImuLogReader> reader;
  if (format == ImuLogFormat::ulog) reader = open_ulog_gyro(in, o.input, {});
  else if (format == ImuLogFormat::imu_tk) reader = open_imu_tk_log(in, o.input, nullptr, "", {0.01, 32768.0, 0.0, 32768.0});
  else reader = open_csv_imu_log(in, o.input, format == ImuLogFormat::ros ? CsvImuDialect::ros : CsvImuDialect::kalibr);
  std::ostream rows(nullptr);
  import_rows(*reader, o, rows);
}

// The ROS library opens bags by name: the bytes go to a file of this process first.
void import_bag(std::string_view input) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / ("gyrosid_fuzz_" + std::to_string(::getpid()) + ".bag");
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(input.data(), static_cast<std::streamsize>(input.size()));
  ImuImportOptions o;
  o.format = ImuLogFormat::rosbag;
  o.input = path.string();
  o.topic = "/imu";
  o.temp_c = 20.0;
  o.stationary = true;
  std::ostream rows(nullptr);
  import_rows(*open_rosbag_imu(o.input, o.topic), o, rows);
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all = [] {
    std::vector<Target> t = {
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
      {"kalibr_csv", {"tests/fuzz/seeds/kalibr_csv/*"}, [](std::string_view in) { import_bytes(ImuLogFormat::kalibr, in); }},
      {"ros_csv", {"tests/fuzz/seeds/ros_csv/*"}, [](std::string_view in) { import_bytes(ImuLogFormat::ros, in); }},
      {"imu_tk", {"tests/fuzz/seeds/imu_tk/*"}, [](std::string_view in) { import_bytes(ImuLogFormat::imu_tk, in); }},
      {"ulog", {"tests/fuzz/seeds/ulog/*"}, [](std::string_view in) { import_bytes(ImuLogFormat::ulog, in); }},
    };
    // Only where gyrosid was built with the ROS 1 bag library (core/rosbag_imu.h).
    if (rosbag_available()) t.push_back({"rosbag", {"tests/fuzz/seeds/rosbag/*"}, [](std::string_view in) { import_bag(in); }});
    return t;
  }();
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
