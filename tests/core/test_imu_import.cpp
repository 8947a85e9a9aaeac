// Importers of other tools' text IMU logs: columns found by name, units converted exactly, times exact, the
// sampling stated, nothing invented silently, errors located.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/imu_import.h"
#include "core/imu_text_logs.h"
#include "core/sample_timing.h"
#include "core/units.h"
#include "error_of.h"
#include "import_test_dir.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing_support::error_of;

class ImuImport : public testing_support::ImportTest {};

ImuImportOptions stationary(ImuLogFormat format, const std::string& input, double temp_c = 21.5) {
  ImuImportOptions o;
  o.format = format;
  o.input = input;
  o.temp_c = temp_c;
  o.stationary = true;
  return o;
}

TEST_F(ImuImport, KalibrNanosecondsAndRadiansBecomeSecondsAndDegrees) {
  const Recording r = import(stationary(ImuLogFormat::kalibr, write("imu0.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n"
                                                                                 "1500000000000000000,0.01,-0.02,0.5,0.1,0.2,9.81\n"
                                                                                 "1500000000005000000,0.011,-0.021,0.51,0.1,0.2,9.80\n")));
  EXPECT_EQ(r.kind(), RecordingKind::triad);
  EXPECT_EQ(r.column("t_s")[1], 0.005);  // exact: integer nanoseconds differenced before conversion
  EXPECT_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(0.5));
  EXPECT_EQ(r.column("accel_z_mps2")[1], 9.80);
  EXPECT_EQ(r.column("ref_rate_x_dps")[1], 0.0);
  EXPECT_EQ(r.column("temp_c")[0], 21.5);
  EXPECT_THAT(r.meta("reference").value_or(""), HasSubstr("stationary"));
  EXPECT_THAT(r.meta("temperature").value_or(""), HasSubstr("given: 21.5 C"));
}

// The header of EuRoC MAV's imu0/data.csv as the dataset ships it, with rows in its form (19-digit ns stamps).
TEST_F(ImuImport, EurocHeaderWithItsHashAndUnitsIsRead) {
  const Recording r = import(stationary(ImuLogFormat::euroc, write("data.csv",
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
      "1403636579758555392,-0.099134701513277898,0.14730578886832138,0.02722713633111154,8.1476917083333333,-0.37592158333333331,-2.4026292499999999\n"
      "1403636579763555584,-0.099134701513277898,0.14032447186034408,0.029321531433504733,8.033280791666666,-0.40861041666666664,-2.4026292499999999\n")));
  EXPECT_EQ(r.column("t_s")[1], 0.005000192);  // 1403636579763555584 - 1403636579758555392 ns
  EXPECT_EQ(r.column("gyro_x_dps")[0], units::radps_to_dps(-0.099134701513277898));
  EXPECT_EQ(r.column("accel_x_mps2")[1], 8.033280791666666);
  EXPECT_EQ(r.meta("time").value_or(""), "t_s is timestamp [ns] less the first (1403636579758555392), exactly");
}

TEST_F(ImuImport, ColumnsAreFoundByNameInAnyOrderAndAccelerometerIsOptional) {
  const Recording r = import(stationary(ImuLogFormat::kalibr, write("imu.csv", "omega_z,note,timestamp,omega_y,omega_x\n"
                                                                                "3,a,100,2,1\n4,b,200,5,6\n")));
  EXPECT_EQ(r.column("gyro_x_dps")[1], units::radps_to_dps(6.0));
  EXPECT_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(3.0));
  EXPECT_EQ(r.column("t_s")[1], 1e-7);
  EXPECT_FALSE(r.has("accel_x_mps2"));
}

TEST_F(ImuImport, TimesAreExactDecimalsOfTheIntegerStamps) {
  // 1.5e18 ns + 30 ms: as doubles, (1500000000030000000 - 1500000000000000000) * 1e-9 is 0.030000000000000002.
  import(stationary(ImuLogFormat::kalibr, write("imu.csv", "timestamp,omega_x,omega_y,omega_z\n"
                                                           "1500000000000000000,0,0,0\n1500000000030000000,0,0,0\n"
                                                           "1500000000060000001,0,0,0\n")));
  EXPECT_EQ(data_line(1).substr(0, 5), "0.03,");
  EXPECT_EQ(data_line(2).substr(0, 12), "0.060000001,");
}

TEST_F(ImuImport, SampleRateIsTheMedianStepAndNonUniformSamplingIsStatedWithItsJitter) {
  Recording r = import(stationary(ImuLogFormat::kalibr, write("u.csv", "timestamp,omega_x,omega_y,omega_z\n0,0,0,0\n5000000,0,0,0\n10000000,0,0,0\n15000000,0,0,0\n")));
  EXPECT_EQ(r.meta("sample_rate_hz").value_or(""), "200");
  EXPECT_THAT(r.meta("sampling").value_or(""), HasSubstr("uniform: every step within 0.01 % of the median 5 ms (3 steps)"));
  EXPECT_TRUE(result_.sampling.uniform);
  // Steps 5, 5, 15, 5 ms: median 5 ms; one step off; rms deviation about the median sqrt(100 / 4) = 5 ms.
  r = import(stationary(ImuLogFormat::kalibr, write("n.csv", "timestamp,omega_x,omega_y,omega_z\n0,0,0,0\n5000000,0,0,0\n10000000,0,0,0\n25000000,0,0,0\n30000000,0,0,0\n")));
  EXPECT_EQ(r.meta("sample_rate_hz").value_or(""), "200");
  EXPECT_EQ(r.meta("sampling").value_or(""),
            "not uniform: 1 of 4 steps differ from the median 5 ms by more than 0.01 %; steps from 5 ms to 15 ms, rms jitter about the median 5 ms");
  EXPECT_FALSE(result_.sampling.uniform);
}

TEST_F(ImuImport, RosRostopicColumnsAreFoundByNameAndTextColumnsIgnored) {
  const Recording r = import(stationary(ImuLogFormat::ros, write("imu.csv", "%time,field.header.seq,field.header.frame_id,field.angular_velocity.x,field.angular_velocity.y,"
                                                                             "field.angular_velocity.z,field.linear_acceleration.x,field.linear_acceleration.y,field.linear_acceleration.z\n"
                                                                             "100,1,imu_link,0.1,0.2,0.3,0,0,9.8\n200,2,imu_link,0.1,0.2,0.3,0,0,9.8\n"),
                                        30.0));
  EXPECT_EQ(r.column("t_s")[1], 1e-7);
  EXPECT_EQ(r.column("gyro_y_dps")[1], units::radps_to_dps(0.2));
}

// The first rows of IMU-TK's Xsens test data (github.com/Kyle-ak/imu_tk, BSD), raw 16-bit counts.
TEST_F(ImuImport, ImuTkCountsScaledAroundTheirOffsetAndTimesExact) {
  ImuImportOptions o = stationary(ImuLogFormat::imu_tk, write("xsens_gyro.mat", "   2.9840000e-02   3.2786000e+04   3.2429000e+04   3.2499000e+04\n"
                                                                                "   3.9857000e-02   3.2797000e+04   3.2410000e+04   3.2531000e+04\n"),
                                  25.0);
  o.accel_input = write("xsens_acc.mat", "   2.9840000e-02   3.3108000e+04   3.3329000e+04   3.6429000e+04\n"
                                         "   3.9857000e-02   3.3096000e+04   3.3336000e+04   3.6437000e+04\n");
  o.gyro_scale_dps_per_count = 0.01, o.accel_scale_mps2_per_count = 0.0025;
  const Recording r = import(o);
  EXPECT_EQ(r.column("gyro_x_dps")[0], (32786.0 - 32768.0) * 0.01);
  EXPECT_EQ(r.column("accel_z_mps2")[1], (36437.0 - 32768.0) * 0.0025);
  EXPECT_EQ(data_line(1).substr(0, 9), "0.010017,");  // 39.857 ms - 29.840 ms, not 0.010017000000000001
}

TEST_F(ImuImport, MissingColumnsAndWrongUnitsAreNamedWithFileAndLine) {
  ImuImportOptions o = stationary(ImuLogFormat::euroc, write("b.csv", "# recorded on the bench\n#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_z [rad s^-1]\n1,0,0\n"));
  EXPECT_THAT(error_of([&] { import(o); }),
              HasSubstr("b.csv:2: no column for the gyro y: 'omega_y' or 'w_RS_S_y' (the header has timestamp [ns], w_RS_S_x [rad s^-1], w_RS_S_z [rad s^-1])"));
  o.input = write("u.csv", "#timestamp [ns],w_RS_S_x [deg s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]\n1,0,0,0\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("u.csv:1: column 'w_RS_S_x [deg s^-1]': the gyro x must be in rad/s, not 'deg s^-1'"));
  o.input = write("a.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_z\n1,0,0,0,0,9.8\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("a.csv:1: no column for the accel y"));
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(ImuImport, NothingIsInventedSilentlyAndErrorsAreLocated) {
  ImuImportOptions o;
  o.input = write("a.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n2,0,0,0,0,0,9.8\n1,0,0,0,0,0,9.8\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("--stationary"));  // no temperature is no error: no temp_c is written
  o.stationary = true;
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("a.csv:3: time stamp 1 does not follow 2"));
  o.input = write("c.csv", "timestamp,omega_x,omega_y,omega_z,alpha_x,alpha_y,alpha_z\n1,0,x,0,0,0,9.8\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("c.csv:2: column 'omega_y': 'x' is not a number"));
  o.input = write("d.csv", "timestamp,omega_x,omega_y,omega_z\n1.5,0,0,0\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("d.csv:2: column 'timestamp': '1.5' is not an integer time stamp in nanoseconds"));
  o.input = write("e.csv", "timestamp,omega_x,omega_y,omega_z\n1,0,0\n");
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("e.csv:2: row has 3 cells, the header has 4"));
  o.format = ImuLogFormat::imu_tk;
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("--gyro-scale-dps-per-count"));
  // A failed import leaves neither the recording nor a temporary behind.
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().extension(), ".csv") << e.path();
  EXPECT_FALSE(fs::exists(out()));
}

TEST(DecimalSeconds, ReadExactlyToTheNanosecond) {
  EXPECT_EQ(decimal_seconds_to_ns("2.9840000e-02"), 29'840'000);
  EXPECT_EQ(decimal_seconds_to_ns("+12.5"), 12'500'000'000);
  EXPECT_EQ(decimal_seconds_to_ns("-1.5"), -1'500'000'000);
  EXPECT_EQ(decimal_seconds_to_ns(".25e1"), 2'500'000'000);
  EXPECT_EQ(decimal_seconds_to_ns("1e-10"), 0);
  EXPECT_EQ(decimal_seconds_to_ns("5e-10"), 1);  // half a nanosecond rounds away from zero
  EXPECT_EQ(decimal_seconds_to_ns("0.1234567894"), 123'456'789);
  EXPECT_EQ(decimal_seconds_to_ns("abc"), std::nullopt);
  EXPECT_EQ(decimal_seconds_to_ns("1e400"), std::nullopt);
  EXPECT_EQ(decimal_seconds_to_ns("1e10"), std::nullopt);  // 1e19 ns overflows
  EXPECT_EQ(decimal_seconds_to_ns("nan"), std::nullopt);
}

TEST(SampleTiming, TicksAreWrittenAsExactDecimals) {
  EXPECT_EQ(ticks_to_seconds_text(30'000'000, 1'000'000'000), "0.03");
  EXPECT_EQ(ticks_to_seconds_text(1, 1'000'000'000), "0.000000001");
  EXPECT_EQ(ticks_to_seconds_text(-1'500'000, 1'000'000), "-1.5");
  EXPECT_EQ(ticks_to_seconds_text(12, 1), "12");
  EXPECT_EQ(ticks_to_seconds_text(INT64_MIN, 1'000'000'000), "-9223372036.854775808");
}

TEST(SampleTiming, HistogramMedianIsExactThenHoldsToItsBinWidth) {
  StepHistogram exact;
  for (std::int64_t s : {5, 5, 7, 5, 100}) exact.add(s);
  EXPECT_EQ(exact.median(), 5.0);
  EXPECT_EQ(exact.count_outside(5.0, 1e-4), 2u);
  EXPECT_EQ(exact.min(), 5);
  EXPECT_EQ(exact.max(), 100);
  // 1000 distinct steps 1000..1999 in 16 bins at most: the median (step 1500) within the bin width.
  StepHistogram coarse(16);
  for (std::int64_t s = 1000; s < 2000; ++s) coarse.add(s);
  EXPECT_GE(coarse.bin_width(), 64);
  EXPECT_NEAR(coarse.median(), 1500.0, static_cast<double>(coarse.bin_width()));
  EXPECT_EQ(coarse.count(), 1000u);
}

}  // namespace
}  // namespace gyrosid
