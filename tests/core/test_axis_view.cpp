// One gyro of a triad under the single-gyro names (core/axis_view.h), and one rate column read alone
// (core/rate_series.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/axis_view.h"
#include "core/rate_series.h"
#include "core/recording.h"
#include "error_of.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using testing_support::error_of;

const char* kTriad =
    "t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps,temp_x_c,temp_y_c,temp_z_c,accel_z_mps2\n"
    "0,1,2,3,1.5,2.5,3.5,20,21,22,9.8\n"
    "1,4,5,6,4.5,5.5,6.5,23,24,25,9.8\n"
    "2,7,8,9,7.5,8.5,9.5,26,27,28,9.8\n";

TEST(AxisView, OneGyroOfATriadUnderTheSingleGyroNames) {
  const Recording triad = parse_recording(kTriad, "triad.csv");
  NamedColumns others;
  const Recording y = single_axis_view(triad, "y", &others);
  EXPECT_EQ(y.kind(), RecordingKind::single);
  EXPECT_EQ(y.names(), (std::vector<std::string>{"t_s", "ref_rate_dps", "gyro_dps", "temp_c", "accel_z_mps2"}));
  EXPECT_EQ(y.column("gyro_dps"), (std::vector<double>{2.5, 5.5, 8.5}));
  EXPECT_EQ(y.column("ref_rate_dps"), (std::vector<double>{2, 5, 8}));
  EXPECT_EQ(y.column("temp_c"), (std::vector<double>{21, 24, 27}));
  ASSERT_EQ(others.size(), 2u);
  EXPECT_EQ(others[0].first, "ref_rate_x_dps");
  EXPECT_EQ(others[1].second, (std::vector<double>{3, 6, 9}));
  // One probe for the triad: every axis reads it.
  const Recording one = single_axis_view(parse_recording("t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps,temp_c\n"
                                                         "0,1,2,3,1,2,3,30\n",
                                                         "one.csv"),
                                         "z");
  EXPECT_EQ(one.column("temp_c"), (std::vector<double>{30}));
  EXPECT_EQ(one.column("gyro_dps"), (std::vector<double>{3}));
  // No thermometer: no temp_c in the view.
  EXPECT_FALSE(single_axis_view(parse_recording("t_s,ref_rate_x_dps,ref_rate_y_dps,ref_rate_z_dps,gyro_x_dps,gyro_y_dps,gyro_z_dps\n0,1,2,3,1,2,3\n", "n.csv"), "x")
                   .has("temp_c"));
}

TEST(AxisView, TheAxisIsAskedForWhereItIsNeededOnly) {
  const Recording triad = parse_recording(kTriad, "triad.csv");
  EXPECT_THAT(error_of([&] { single_axis_view(triad, ""); }), HasSubstr("triad.csv: a triad recording; choose the gyro with --axis x|y|z"));
  EXPECT_THAT(error_of([&] { single_axis_view(triad, "w"); }), HasSubstr("--axis 'w' must be x, y or z"));
  const Recording single = parse_recording("t_s,ref_rate_dps,gyro_dps\n0,0,0\n", "s.csv");
  EXPECT_THAT(error_of([&] { single_axis_view(single, "x"); }), HasSubstr("s.csv: --axis x applies to triad recordings only"));
  EXPECT_EQ(single_axis_view(single, "").names(), single.names());
}

class RateFile {
 public:
  explicit RateFile(const std::string& text) : path_(std::filesystem::temp_directory_path() / ("gyrosid_rate_" + std::to_string(::getpid()) + ".csv")) {
    std::ofstream(path_) << text;
  }
  ~RateFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(RateSeries, OneColumnMinusAnotherInDegreesPerHour) {
  RateFile f(kTriad);
  const RateSeries z = read_rate_series(f.path(), {"gyro_dps", "ref_rate_dps", "z", "the Allan deviation"});
  EXPECT_EQ(z.column, "gyro_z_dps");
  EXPECT_EQ(z.subtract, "ref_rate_z_dps");
  EXPECT_EQ(z.rate_dph, (std::vector<double>{0.5 * 3600, 0.5 * 3600, 0.5 * 3600}));
  EXPECT_DOUBLE_EQ(z.dt_s, 1.0);
  EXPECT_EQ(z.reference_max_dph, 0.0);  // subtracted: no warning about the motion
  const RateSeries x = read_rate_series(f.path(), {"gyro_dps", "", "x", "the Allan deviation"});
  EXPECT_DOUBLE_EQ(x.reference_max_dph - x.reference_min_dph, 6.0 * 3600);
  EXPECT_THAT(error_of([&] { read_rate_series(f.path(), {"temp_c", "", "x", "the Allan deviation"}); }), HasSubstr("'temp_x_c' is not a rate"));
}

TEST(RateSeries, NonUniformSamplingIsRefusedAtItsLine) {
  RateFile f("t_s,ref_rate_dps,gyro_dps\n0,0,1\n1,0,1\n2,0,1\n# a note\n4,0,1\n");
  EXPECT_THAT(error_of([&] { read_rate_series(f.path(), {}); }), HasSubstr(":6: the Allan deviation needs uniform sampling, but the step here is 2 s"));
}

}  // namespace
}  // namespace gyrosid
