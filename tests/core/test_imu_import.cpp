// Importers of other tools' IMU logs: units converted exactly, nothing invented silently, errors located.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/imu_import.h"
#include "core/units.h"
#include "error_of.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing_support::error_of;

class ImuImport : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  // One directory per test and process: ctest runs this fixture's tests in parallel processes.
  fs::path dir_ = fs::temp_directory_path() /
                  ("gyrosid_imu_import_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" + std::to_string(getpid()));
};

TEST_F(ImuImport, KalibrNanosecondsAndRadiansBecomeSecondsAndDegrees) {
  ImuImportOptions o;
  o.input = write("imu0.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n"
                              "1500000000000000000,0.01,-0.02,0.5,0.1,0.2,9.81\n"
                              "1500000000005000000,0.011,-0.021,0.51,0.1,0.2,9.80\n");
  o.temp_c = 21.5;
  o.stationary = true;
  const Recording r = import_imu_log(o);
  EXPECT_EQ(r.kind(), RecordingKind::triad);
  EXPECT_EQ(r.column("t_s")[1], 0.005);  // exact: integer nanoseconds differenced before conversion
  EXPECT_DOUBLE_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(0.5));
  EXPECT_DOUBLE_EQ(r.column("accel_z_mps2")[1], 9.80);
  EXPECT_EQ(r.column("ref_rate_x_dps")[1], 0.0);
  EXPECT_EQ(r.column("temp_c")[0], 21.5);
  EXPECT_THAT(r.meta("reference").value_or(""), HasSubstr("stationary"));
}

TEST_F(ImuImport, RosRostopicColumnsAreFoundByName) {
  ImuImportOptions o;
  o.format = ImuLogFormat::ros;
  o.input = write("imu.csv", "%time,field.header.seq,field.angular_velocity.x,field.angular_velocity.y,field.angular_velocity.z,"
                             "field.linear_acceleration.x,field.linear_acceleration.y,field.linear_acceleration.z\n"
                             "100,1,0.1,0.2,0.3,0,0,9.8\n200,2,0.1,0.2,0.3,0,0,9.8\n");
  o.temp_c = 30.0;
  o.stationary = true;
  const Recording r = import_imu_log(o);
  EXPECT_DOUBLE_EQ(r.column("t_s")[1], 1e-7);
  EXPECT_DOUBLE_EQ(r.column("gyro_y_dps")[1], units::radps_to_dps(0.2));
}

// The first rows of IMU-TK's Xsens test data (github.com/Kyle-ak/imu_tk, BSD), raw 16-bit counts.
TEST_F(ImuImport, ImuTkCountsScaledAroundTheirOffset) {
  ImuImportOptions o;
  o.format = ImuLogFormat::imu_tk;
  o.input = write("xsens_gyro.mat", "   2.9840000e-02   3.2786000e+04   3.2429000e+04   3.2499000e+04\n"
                                    "   3.9857000e-02   3.2797000e+04   3.2410000e+04   3.2531000e+04\n");
  o.accel_input = write("xsens_acc.mat", "   2.9840000e-02   3.3108000e+04   3.3329000e+04   3.6429000e+04\n"
                                         "   3.9857000e-02   3.3096000e+04   3.3336000e+04   3.6437000e+04\n");
  o.gyro_scale_dps_per_count = 0.01, o.accel_scale_mps2_per_count = 0.0025;
  o.temp_c = 25.0;
  o.stationary = true;
  const Recording r = import_imu_log(o);
  EXPECT_NEAR(r.column("gyro_x_dps")[0], (32786.0 - 32768.0) * 0.01, 1e-12);
  EXPECT_NEAR(r.column("accel_z_mps2")[1], (36437.0 - 32768.0) * 0.0025, 1e-12);
  EXPECT_NEAR(r.column("t_s")[1], 3.9857e-02, 1e-15);
}

TEST_F(ImuImport, NothingIsInventedSilentlyAndErrorsAreLocated) {
  ImuImportOptions o;
  o.input = write("a.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n2,0,0,0,0,0,9.8\n1,0,0,0,0,0,9.8\n");
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("--temp-c"));
  o.temp_c = 20.0;
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("--stationary"));
  o.stationary = true;
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("a.csv:3: the time stamp does not increase"));
  o.input = write("b.csv", "timestamp,omega_x,omega_y,omega_z\n1,0,0,0\n");
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("b.csv: missing column 'alpha_x'"));
  o.input = write("c.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n1,0,x,0,0,0,9.8\n");
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("c.csv:2: column 'omega_y': 'x' is not a number"));
  o.format = ImuLogFormat::imu_tk;
  EXPECT_THAT(error_of([&] { import_imu_log(o); }), HasSubstr("--gyro-scale-dps-per-count"));
}

}  // namespace
}  // namespace gyrosid
