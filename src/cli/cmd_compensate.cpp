// gyrosid compensate: apply a calibration model to a recording (model/compensate_recording.h).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/error.h"
#include "core/format.h"
#include "model/compensate_recording.h"

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
      const bool triad = is_triad_model_file(o->model);
      if (triad && !o->axis.empty()) fail("--axis applies to a single-gyro model; a triad model compensates all three gyros");
      CompensatedRecording r;
      if (triad) {
        r = compensate_triad_recording(load_triad_model(o->model), read_recording(o->recording));
        write_recording(r.recording, o->out);
      } else {
        r = compensate_file(*load_model(o->model), o->recording, o->out, o->axis);
      }
      const std::string added = triad ? "compensated_{x,y,z}_dps" : o->axis.empty() ? "compensated_dps" : "compensated_" + o->axis + "_dps";
      std::cout << "wrote " << o->out << ": " << r.samples << " samples with " << added;
      if (r.rms_before_dph) {
        std::cout << "; rms error against " << (triad ? "ref_rate_{x,y,z}_dps " : "ref_rate_dps ") << format_significant(*r.rms_before_dph, 4) << " -> "
                  << format_significant(*r.rms_after_dph, 4) << " deg/h";
        if (r.coverage_95) std::cout << "; the 95 % predictive band (compensated_sigma_dps) covers " << format_significant(100 * *r.coverage_95, 3) << " %";
      }
      std::cout << "\n";
    };
  });
}

}  // namespace gyrosid::cli
