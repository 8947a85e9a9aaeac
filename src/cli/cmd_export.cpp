// gyrosid export: a model as dependency-free C99, or a triad model as a Kalibr IMU YAML.
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "model/sensor_model.h"
#include "model/triad_export.h"

namespace gyrosid::cli {
namespace {

struct ExportOptions {
  std::string model, prefix = "gyro", out, format = "c";
};

// What Kalibr's YAML takes beside the model from a triad model file `j` (read from `path`).
KalibrExportInfo kalibr_info(const nlohmann::json& j, const std::string& path) {
  KalibrExportInfo info;
  info.source = path;
  if (j.contains("noise_density_radps_rt_hz")) {
    for (std::size_t a = 0; a < 3; ++a) {
      const auto& v = j["noise_density_radps_rt_hz"][a];
      info.noise_density[a] = v.is_number() ? v.get<double>() : 0.0;
    }
  }
  info.update_rate_hz = j.value("sample_rate_hz", 0.0);
  return info;
}

void run_export(const ExportOptions& o) {
  const nlohmann::json file = load_model_json(o.model);
  const std::unique_ptr<SensorModel> model = sensor_model_from_json(file, o.model);
  if (o.format == "kalibr") {
    const auto* triad = dynamic_cast<const TriadModel*>(model.get());
    if (!triad) fail("--format kalibr needs a triad model (calibrate --model triad); ", o.model, " is a ", model->kind(), " model of one gyro");
    const std::filesystem::path yaml = std::filesystem::path(o.out) / (o.prefix + "_imu.yaml");
    write_file_atomic(yaml, kalibr_imu_yaml(*triad, kalibr_info(file, o.model)));
    std::cout << "wrote " << yaml.string() << "\n";
    return;
  }
  if (o.format != "c") fail("--format '", o.format, "': expected c or kalibr");
  model->export_c(o.out, o.prefix);
  std::cout << "wrote " << o.out << "/" << o.prefix << ".h and " << o.prefix << ".c\n";
}

}  // namespace

void register_export(CLI::App& app, Action& action) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Export a model to dependency-free C99 (<prefix>.h, <prefix>.c) or a triad model to Kalibr");
  cmd->add_option("--model", o->model, "Model file written by calibrate")->required();
  cmd->add_option("--format", o->format, "c (default) or kalibr (triad models: <prefix>_imu.yaml, scale-misalignment)")->capture_default_str();
  cmd->add_option("--prefix", o->prefix, "C identifier prefix / file name prefix")->capture_default_str();
  cmd->add_option("--out", o->out, "Output directory")->required();
  cmd->footer(
      "A triad model exports to C as <prefix>_compensate(gyro_radps[3], temp_c[3], f_mps2[3], omega_radps[3]),\n"
      "and to Kalibr's IMU YAML (M, C_gyro_i, A of its scale-misalignment model; units in comments).");
  cmd->callback([o, &action] { action = [o] { run_export(*o); }; });
}

}  // namespace gyrosid::cli
