// PX4 ULog import: planted values read back exactly (a log written by tests/core/ulog_test_writer.h), the
// format's corners (nested types, trailing padding, dropouts, truncation, appended data, unknown flags), and a
// real PX4 log read as pyulog (PX4's own Python reader) reads it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/imu_import.h"
#include "core/sample_timing.h"
#include "core/units.h"
#include "error_of.h"
#include "import_test_dir.h"
#include "ulog_test_writer.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using testing_support::error_of;
using testing_support::Packer;
using testing_support::UlogWriter;

// sensor_gyro with a nested type (vec3, defined after its use) before x, and a trailing padding that the data
// messages leave out, as PX4's logger does.
constexpr const char* kGyroFormat =
    "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;vec3 bias;float x;float y;float z;"
    "float temperature;uint32_t error_count;uint8_t[4] _padding0;";

Packer gyro(std::uint64_t t_sample_us, float x, float y, float z, float temp_c) {
  Packer p;
  p.put(t_sample_us + 150).put(t_sample_us).put(std::uint32_t{7}).put(9.0f).put(9.0f).put(9.0f);
  p.put(x).put(y).put(z).put(temp_c).put(std::uint32_t{0});
  return p;
}

// Instance 1's sample k: 250 Hz from 5 s, planted values exact in float.
constexpr std::uint64_t kStart = 5'000'000, kStep = 4000;
float x_of(int k) { return 0.125f * static_cast<float>(k); }
float temp_of(int k) { return 30.0f + 0.25f * static_cast<float>(k); }

// Definitions, two instances' subscriptions, then n samples of each (instance 0 planted with x = 99).
UlogWriter planted_log(int n) {
  UlogWriter w;
  w.flag_bits();
  w.format(kGyroFormat).format("vec3:float[3] v;").info("char[3] sys_name", "PX4").info("char[9] ver_hw", "TESTBOARD");
  w.subscribe(0, 0, "sensor_gyro").subscribe(1, 1, "sensor_gyro").logging("[logger] started");
  for (int k = 0; k < n; ++k) {
    w.data(0, gyro(kStart + kStep * static_cast<std::uint64_t>(k) + 13, 99.0f, 99.0f, 99.0f, 99.0f));
    w.data(1, gyro(kStart + kStep * static_cast<std::uint64_t>(k), x_of(k), -0.5f, 1.0f / 1024.0f, temp_of(k)));
    if (k % 3 == 0) w.sync();
  }
  return w;
}

class UlogImport : public testing_support::ImportTest {
 protected:
  ImuImportOptions options(const std::string& bytes, int instance = 1) {
    ImuImportOptions o;
    o.format = ImuLogFormat::ulog;
    o.input = write("log.ulg", bytes);
    o.instance = instance;
    o.stationary = true;
    return o;
  }
};

TEST_F(UlogImport, PlantedSensorGyroReadsBackExactlyWithItsTemperature) {
  const Recording r = import(options(planted_log(10).str()));
  ASSERT_EQ(r.rows(), 10u);
  for (int k = 0; k < 10; ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_EQ(r.column("t_s")[i], std::stod(ticks_to_seconds_text(k * 4000, 1'000'000)));
    EXPECT_EQ(r.column("gyro_x_dps")[i], units::radps_to_dps(static_cast<double>(x_of(k))));
    EXPECT_EQ(r.column("gyro_y_dps")[i], units::radps_to_dps(-0.5));
    EXPECT_EQ(r.column("gyro_z_dps")[i], units::radps_to_dps(1.0 / 1024.0));
    EXPECT_EQ(r.column("temp_c")[i], static_cast<double>(temp_of(k)));
  }
  EXPECT_EQ(data_line(1).substr(0, 6), "0.004,");
  EXPECT_EQ(r.meta("sample_rate_hz").value_or(""), "250");
  EXPECT_THAT(r.meta("sampling").value_or(""), HasSubstr("uniform"));
  EXPECT_EQ(r.meta("time").value_or(""), "t_s is sensor_gyro.timestamp_sample [us] less the first (5000000), exactly");
  EXPECT_EQ(r.meta("temperature").value_or(""), "from the log: sensor_gyro.temperature");
  EXPECT_EQ(r.meta("sensor").value_or(""), "PX4, board TESTBOARD, sensor_gyro instance 1");
  EXPECT_TRUE(result_.warnings.empty());
}

TEST_F(UlogImport, GivenTemperatureReplacesTheLogsAndSaysSo) {
  ImuImportOptions o = options(planted_log(3).str());
  o.temp_c = 21.0;
  const Recording r = import(o);
  EXPECT_EQ(r.column("temp_c")[2], 21.0);
  EXPECT_EQ(r.meta("temperature").value_or(""), "given: 21 C (replaces the log's sensor_gyro.temperature)");
}

TEST_F(UlogImport, DropoutsAreNotedAndTheirGapShowsInTheSampling) {
  UlogWriter w = planted_log(4);
  w.dropout(12);  // samples 4..6 lost
  for (int k = 7; k < 9; ++k) w.data(1, gyro(kStart + kStep * static_cast<std::uint64_t>(k), x_of(k), -0.5f, 0.0f, temp_of(k)));
  const Recording r = import(options(w.str()));
  ASSERT_EQ(r.rows(), 6u);
  EXPECT_EQ(r.column("t_s")[4], 0.028);
  EXPECT_EQ(r.column("gyro_x_dps")[5], units::radps_to_dps(static_cast<double>(x_of(8))));
  EXPECT_THAT(r.meta("dropouts").value_or(""), HasSubstr("1 in the log (12 ms in all)"));
  EXPECT_THAT(r.meta("sampling").value_or(""), HasSubstr("not uniform: 1 of 5 steps"));
  ASSERT_EQ(result_.warnings.size(), 1u);
  EXPECT_THAT(result_.warnings[0], HasSubstr("log.ulg: dropouts: 1 in the log"));
}

TEST_F(UlogImport, TruncatedLogKeepsTheDataUpToTheCutWithAWarning) {
  const std::string full = planted_log(5).str();
  const std::string cut = full.substr(0, full.size() - 7);  // inside instance 1's last message (the last message)
  const Recording r = import(options(cut));
  EXPECT_EQ(r.rows(), 4u);
  EXPECT_EQ(r.column("gyro_x_dps")[3], units::radps_to_dps(static_cast<double>(x_of(3))));
  ASSERT_EQ(result_.warnings.size(), 1u);
  EXPECT_THAT(result_.warnings[0], HasSubstr("it was discarded (truncated log)"));
  // Cut inside the definitions: no data to import, said so.
  EXPECT_THAT(error_of([&] { import(options(full.substr(0, 60))); }), HasSubstr("no sensor_gyro or sensor_combined data for instance 1"));
}

TEST_F(UlogImport, AppendedDataAreReadAndTheMessageTheyCutIsDiscarded) {
  UlogWriter w;
  const std::size_t offsets_at = w.flag_bits(1);  // DATA_APPENDED
  w.format(kGyroFormat).format("vec3:float[3] v;").subscribe(1, 3, "sensor_gyro");
  for (int k = 0; k < 3; ++k) w.data(3, gyro(kStart + kStep * static_cast<std::uint64_t>(k), x_of(k), 0.0f, 0.0f, temp_of(k)));
  UlogWriter cut_message;
  cut_message.data(3, gyro(kStart + kStep * 3, 77.0f, 0.0f, 0.0f, 0.0f));
  const std::string partial = cut_message.str().substr(16, 20);  // the log stopped inside this message
  w.raw(std::vector<std::uint8_t>(partial.begin(), partial.end()));
  w.patch_u64(offsets_at, w.size());
  w.data(3, gyro(kStart + kStep * 4, x_of(4), 0.0f, 0.0f, temp_of(4)));  // the appended data
  const Recording r = import(options(w.str()));
  ASSERT_EQ(r.rows(), 4u);
  EXPECT_EQ(r.column("gyro_x_dps")[3], units::radps_to_dps(static_cast<double>(x_of(4))));
  EXPECT_EQ(r.column("t_s")[3], 0.016);
  EXPECT_THAT(r.meta("appended_data").value_or(""), HasSubstr("read as part of the data section"));
  EXPECT_THAT(r.meta("log_damage").value_or(""), HasSubstr("was discarded"));
}

TEST_F(UlogImport, DamagedMessagesElsewhereAreSkippedAndNoted) {
  UlogWriter w = planted_log(3);
  w.format("no colon here").data(9, Packer().put(std::uint64_t{1})).message('Z', {1, 2, 3});  // bad format, orphan data, unknown type
  const Recording r = import(options(w.str()));
  EXPECT_EQ(r.rows(), 3u);
  EXPECT_EQ(r.meta("skipped_messages").value_or(""),
            "1 malformed (too short for their type, or a format that does not parse) and 1 data messages of no subscription (a damaged log?)");
  EXPECT_THAT(r.meta("unknown_messages").value_or(""), HasSubstr("1 of types this reader does not know"));
}

TEST_F(UlogImport, SensorCombinedWhenNoSensorGyroHasTheTemperatureOnlyWhenGiven) {
  UlogWriter w;
  w.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;").subscribe(0, 0, "sensor_combined");
  for (int k = 0; k < 3; ++k) w.data(0, Packer().put(std::uint64_t{1000} + 5000 * static_cast<std::uint64_t>(k)).put(0.5f).put(x_of(k)).put(-2.0f).put(std::uint32_t{5000}));
  ImuImportOptions o = options(w.str(), 0);
  EXPECT_FALSE(import(o).has("temp_c"));  // sensor_combined has no temperature: none is written unless given
  o.temp_c = 22.0;
  const Recording r = import(o);
  ASSERT_EQ(r.rows(), 3u);
  EXPECT_EQ(r.column("gyro_y_dps")[2], units::radps_to_dps(static_cast<double>(x_of(2))));
  EXPECT_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(-2.0));
  EXPECT_EQ(r.meta("sample_rate_hz").value_or(""), "200");
}

TEST_F(UlogImport, RefusedLogsAreNamed) {
  EXPECT_THAT(error_of([&] { import(options("timestamp,omega_x\n1,2\n")); }), HasSubstr("log.ulg: not a ULog file"));
  UlogWriter flags;
  flags.flag_bits(0, 1);
  EXPECT_THAT(error_of([&] { import(options(flags.str())); }), HasSubstr("log.ulg: byte 16: the log sets incompatible flag bits"));
  EXPECT_THAT(error_of([&] { import(options(planted_log(2).str(), 2)); }),
              HasSubstr("log.ulg: no sensor_gyro or sensor_combined data for instance 2; it has sensor_gyro data for instance(s) 0, 1 (--instance)"));
  UlogWriter loop;
  loop.format("sensor_gyro:uint64_t timestamp;loop_a a;float x;float y;float z;").format("loop_a:loop_b b;").format("loop_b:loop_a a;");
  loop.subscribe(0, 0, "sensor_gyro").data(0, Packer().put(std::uint64_t{1}));
  EXPECT_THAT(error_of([&] { import(options(loop.str(), 0)); }), HasSubstr("circular definition"));
  ImuImportOptions o = options(planted_log(2).str());
  o.topic = "vehicle_attitude";
  EXPECT_THAT(error_of([&] { import(o); }), HasSubstr("--topic for a ulog log is sensor_gyro or sensor_combined"));
}

// pyulog's test log test/sample_log_small.ulg (BSD-3-Clause; tests/data/pyulog/README.md): a CubeOrange on the
// bench, three gyros logged at 1 Hz, sensor_combined at about 200 Hz, one 30 ms dropout. The expected values are
// pyulog 3cf1779's (ULog('sample_log_small.ulg'), its float32 fields), an independent reader.
TEST_F(UlogImport, RealPx4LogReadsAsPyulogReadsIt) {
  ImuImportOptions o;
  o.format = ImuLogFormat::ulog;
  o.input = std::string(GYROSID_TEST_DATA) + "/pyulog/sample_log_small.ulg";
  o.instance = 1;
  o.stationary = true;
  Recording r = import(o);
  ASSERT_EQ(r.rows(), 6u);
  EXPECT_EQ(r.column("t_s")[5], 5.0);  // timestamp_sample 26310770 - 21310770 us
  EXPECT_EQ(r.column("gyro_x_dps")[0], units::radps_to_dps(static_cast<double>(0.017656758f)));
  EXPECT_EQ(r.column("gyro_y_dps")[5], units::radps_to_dps(static_cast<double>(0.0022488916f)));
  EXPECT_EQ(r.column("gyro_z_dps")[0], units::radps_to_dps(static_cast<double>(-0.006178534f)));
  EXPECT_EQ(r.column("temp_c")[0], static_cast<double>(28.246023f));
  EXPECT_EQ(r.column("temp_c")[5], static_cast<double>(28.367332f));
  EXPECT_EQ(r.meta("sensor").value_or(""), "PX4, board CUBEPILOT_CUBEORANGE, sensor_gyro instance 1");
  EXPECT_THAT(r.meta("dropouts").value_or(""), HasSubstr("1 in the log (30 ms in all)"));
  o.instance = 0;
  o.topic = "sensor_combined";
  o.temp_c = 25.0;
  r = import(o);
  ASSERT_EQ(r.rows(), 1298u);
  EXPECT_EQ(r.column("t_s").back(), 6.496152);  // timestamp 26822868 - 20326716 us
  EXPECT_EQ(r.column("gyro_z_dps").back(), units::radps_to_dps(static_cast<double>(0.0007792017f)));
}

}  // namespace
}  // namespace gyrosid
