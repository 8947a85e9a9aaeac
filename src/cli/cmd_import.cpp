// gyrosid import: an IMU log in another tool's format (Kalibr/EuRoC, ROS, IMU-TK, PX4 ULog, ROS 1 bag) as a
// gyrosid recording.
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/format.h"
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
  CLI::App* cmd = app.add_subcommand("import", "Convert an IMU log (Kalibr/EuRoC CSV, ROS CSV or bag, IMU-TK text, PX4 ULog) into a recording");
  cmd->add_option("--format", o->format, "kalibr, euroc, ros, imu_tk, ulog or rosbag")->capture_default_str();
  cmd->add_option("--input", o->import.input, "The log (imu_tk: the gyro file)")->required();
  cmd->add_option("--accel-input", o->import.accel_input, "imu_tk: the accelerometer file (same time stamps)");
  auto* temp = cmd->add_option("--temp-c", o->temp_c, "Temperature to record (deg C): replaces the log's if given; a log without one (all but ulog sensor_gyro) and no --temp-c gives a recording without temp_c, which noise work (allan, explain) reads and calibrate refuses");
  cmd->add_flag("--stationary", o->import.stationary, "The IMU did not move: the true rate is written as zero");
  cmd->add_option("--topic", o->import.topic, "rosbag: the sensor_msgs/Imu topic; ulog: sensor_gyro or sensor_combined (default: sensor_gyro if logged)");
  cmd->add_option("--instance", o->import.instance, "ulog: the topic's instance (multi_id), one per gyro")->capture_default_str();
  cmd->add_option("--gyro-scale-dps-per-count", o->import.gyro_scale_dps_per_count, "imu_tk: gyro counts to deg/s");
  cmd->add_option("--gyro-offset-counts", o->import.gyro_offset_counts, "imu_tk: the gyro's zero in counts")->capture_default_str();
  cmd->add_option("--accel-scale-mps2-per-count", o->import.accel_scale_mps2_per_count, "imu_tk: accel counts to m/s^2");
  cmd->add_option("--accel-offset-counts", o->import.accel_offset_counts, "imu_tk: the accelerometer's zero in counts")->capture_default_str();
  cmd->add_option("--out", o->out, "Recording to write (a triad recording)")->required();
  cmd->footer(
      "Formats (columns found by name, in any order):\n"
      "  kalibr, euroc  CSV: Kalibr's timestamp,omega_x..z,alpha_x..z or EuRoC's imu0/data.csv\n"
      "                 (#timestamp [ns],w_RS_S_x [rad s^-1],...,a_RS_S_x [m s^-2],...); stamps in integer ns\n"
      "  ros            `rostopic echo -p /imu` of sensor_msgs/Imu (%time, field.angular_velocity.x, ...)\n"
      "  imu_tk         IMU-TK text: 't x y z' rows of raw counts (--gyro-scale-dps-per-count, --accel-input)\n"
      "  ulog           PX4 ULog: sensor_gyro (instance --instance) with its temperature, the data PX4's thermal\n"
      "                 calibration uses; sensor_combined's gyro_rad when the log has no sensor_gyro\n"
      "  rosbag         ROS 1 bag: sensor_msgs/Imu on --topic (header.stamp)\n"
      "No log records the true rate, and only ULog's sensor_gyro a temperature: the importer writes what you state\n"
      "(--stationary, --temp-c) and says so in the metadata, with the median sample_rate_hz and whether the sampling\n"
      "is uniform. Times are the log's integer stamps less the first, exactly. The import streams (bounded memory).\n"
      "Examples:\n"
      "  gyrosid import --format euroc --input mav0/imu0/data.csv --stationary --out static.csv     # no thermometer: no temp_c\n"
      "  gyrosid import --format kalibr --input imu0.csv --stationary --temp-c 22 --out static.csv\n"
      "  gyrosid import --format ros --input imu.csv --stationary --temp-c 22 --out static.csv\n"
      "  gyrosid import --format imu_tk --input xsens_gyro.mat --accel-input xsens_acc.mat \\\n"
      "      --gyro-scale-dps-per-count 0.01 --accel-scale-mps2-per-count 0.0025 --stationary --temp-c 25 --out tk.csv\n"
      "  gyrosid import --format ulog --input thermal.ulg --instance 0 --stationary --out thermal.csv\n"
      "  gyrosid import --format rosbag --input static.bag --topic /imu --stationary --temp-c 22 --out static.csv\n"
      "  gyrosid allan --recording static.csv --column gyro_x_dps --kalibr imu.yaml --out allan_x/");
  cmd->callback([o, temp, &action] {
    action = [o, temp] {
      o->import.format = parse_enum<ImuLogFormat>(o->format, "--format");
      if (temp->count() > 0) o->import.temp_c = o->temp_c;
      const ImportResult r = import_imu_log(o->import, o->out);
      for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
      std::cout << "wrote " << o->out << ": " << r.rows << " samples from " << o->format << " log " << o->import.input;
      if (r.sampling.rate_hz > 0) std::cout << ", " << format_significant(r.sampling.rate_hz, 6) << " Hz (median)";
      std::cout << "; sampling " << r.sampling.description << "\n";
    };
  });
}

}  // namespace gyrosid::cli
