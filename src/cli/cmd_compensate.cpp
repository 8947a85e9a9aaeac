// gyrosid compensate: apply a model file of any kind to a recording (model/sensor_model.h, compensate_recording.h).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/error.h"
#include "core/format.h"
#include "model/sensor_model.h"

namespace gyrosid::cli {

void register_compensate(CLI::App& app, Action& action) {
  struct CompensateOptions {
    std::string model, recording, out, axis;
  };
  auto o = std::make_shared<CompensateOptions>();
  CLI::App* cmd = app.add_subcommand("compensate", "Apply a calibration model: the recording plus compensated_dps (a triad model: compensated_{x,y,z}_dps)");
  cmd->add_option("--model", o->model, "Model file written by calibrate")->required();
  cmd->add_option("--recording", o->recording, "Recording to compensate")->required();
  cmd->add_option("--out", o->out, "Recording to write")->required();
  cmd->add_option("--axis", o->axis, "Triad recordings: the gyro a single-gyro model compensates (x, y or z); adds compensated_<axis>_dps");
  cmd->callback([o, &action] {
    action = [o] {
      const CompensatedRecording r = load_sensor_model(o->model)->compensate_file(o->recording, o->out, o->axis);
      std::cout << "wrote " << o->out << ": " << r.samples << " samples with " << r.added;
      if (r.rms_before_dph) {
        std::cout << "; rms error against " << r.reference << " " << format_significant(*r.rms_before_dph, 4) << " -> "
                  << format_significant(*r.rms_after_dph, 4) << " deg/h";
        if (r.coverage_95) std::cout << "; the 95 % predictive band (compensated_sigma_dps) covers " << format_significant(100 * *r.coverage_95, 3) << " %";
      }
      std::cout << "\n";
    };
  });
}

}  // namespace gyrosid::cli
