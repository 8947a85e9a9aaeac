// gyrosid import: an IMU log in another tool's format (Kalibr, ROS, IMU-TK) as a gyrosid recording.
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/imu_import.h"

namespace gyrosid::cli {

void register_import(CLI::App& app, Action& action) {
  struct Options {
    ImuImportOptions import;
    std::string format = "kalibr";
    std::string out;
    double temp_c = 0.0;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("import", "Convert an IMU log (Kalibr CSV, ROS rostopic CSV, IMU-TK text) into a recording");
  cmd->add_option("--format", o->format, "kalibr, ros or imu_tk")->capture_default_str();
  cmd->add_option("--input", o->import.input, "The log (imu_tk: the gyro file)")->required();
  cmd->add_option("--accel-input", o->import.accel_input, "imu_tk: the accelerometer file (same time stamps)");
  auto* temp = cmd->add_option("--temp-c", o->temp_c, "Temperature to record (the logs have none)");
  cmd->add_flag("--stationary", o->import.stationary, "The IMU did not move: the true rate is written as zero");
  cmd->add_option("--gyro-scale-dps-per-count", o->import.gyro_scale_dps_per_count, "imu_tk: gyro counts to deg/s");
  cmd->add_option("--gyro-offset-counts", o->import.gyro_offset_counts, "imu_tk: the gyro's zero in counts")->capture_default_str();
  cmd->add_option("--accel-scale-mps2-per-count", o->import.accel_scale_mps2_per_count, "imu_tk: accel counts to m/s^2");
  cmd->add_option("--accel-offset-counts", o->import.accel_offset_counts, "imu_tk: the accelerometer's zero in counts")->capture_default_str();
  cmd->add_option("--out", o->out, "Recording to write (a triad recording)")->required();
  cmd->footer(
      "Kalibr: timestamp [ns], omega_x..z [rad/s], alpha_x..z [m/s^2]. ROS: `rostopic echo -p /imu` of sensor_msgs/Imu.\n"
      "IMU-TK: 't x y z' rows of raw counts. The logs record neither the true rate nor a temperature; the importer\n"
      "writes what you state (--stationary, --temp-c) and says so in the recording's metadata.\n"
      "Example: gyrosid import --format kalibr --input imu0.csv --stationary --temp-c 22 --out static.csv\n"
      "         gyrosid allan --recording static.csv --column gyro_x_dps --kalibr imu.yaml --out allan_x/");
  cmd->callback([o, temp, &action] {
    action = [o, temp] {
      o->import.format = parse_enum<ImuLogFormat>(o->format, "--format");
      if (temp->count() > 0) o->import.temp_c = o->temp_c;
      const Recording rec = import_imu_log(o->import);
      write_recording(rec, o->out);
      std::cout << "wrote " << o->out << ": " << rec.rows() << " samples from " << o->format << " log " << o->import.input << "\n";
    };
  });
}

}  // namespace gyrosid::cli
