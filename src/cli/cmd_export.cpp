// gyrosid export: a model as dependency-free C99.
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "model/calibration_model.h"

namespace gyrosid::cli {

void register_export(CLI::App& app, Action& action) {
  struct ExportOptions {
    std::string model, prefix = "gyro", out;
  };
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Export a model to dependency-free C99 (<prefix>.h, <prefix>.c)");
  cmd->add_option("--model", o->model, "Model file written by calibrate")->required();
  cmd->add_option("--prefix", o->prefix, "C identifier prefix")->capture_default_str();
  cmd->add_option("--out", o->out, "Output directory")->required();
  cmd->callback([o, &action] {
    action = [o] {
      load_model(o->model)->export_c(o->out, o->prefix);
      std::cout << "wrote " << o->out << "/" << o->prefix << ".h and " << o->prefix << ".c\n";
    };
  });
}

}  // namespace gyrosid::cli
