// gyrosid compensate: apply a calibration model to a recording (model/compensate_recording.h).
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/format.h"
#include "model/compensate_recording.h"

namespace gyrosid::cli {

void register_compensate(CLI::App& app, Action& action) {
  struct CompensateOptions {
    std::string model, recording, out;
  };
  auto o = std::make_shared<CompensateOptions>();
  CLI::App* cmd = app.add_subcommand("compensate", "Apply a calibration model: the recording plus compensated_dps (a triad model: compensated_{x,y,z}_dps)");
  cmd->add_option("--model", o->model, "Model file written by calibrate")->required();
  cmd->add_option("--recording", o->recording, "Recording to compensate")->required();
  cmd->add_option("--out", o->out, "Recording to write")->required();
  cmd->callback([o, &action] {
    action = [o] {
      const bool triad = is_triad_model_file(o->model);
      const CompensatedRecording r = triad ? compensate_triad_recording(load_triad_model(o->model), read_recording(o->recording))
                                           : compensate_recording(*load_model(o->model), read_recording(o->recording));
      write_recording(r.recording, o->out);
      std::cout << "wrote " << o->out << ": " << r.recording.rows() << " samples with " << (triad ? "compensated_{x,y,z}_dps" : "compensated_dps");
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
