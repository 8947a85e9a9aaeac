// Block means (core/decimation.h): interval means at b dt, never across a gap, the spreads stated; the noise
// processes at b dt; a file read with block means equals the recording decimated in memory.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numeric>

#include "core/decimation.h"
#include "core/format.h"
#include "core/random.h"
#include "core/recording.h"
#include "error_of.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;

Recording uniform(const std::vector<double>& gyro, double dt, std::vector<double> ref = {}) {
  Recording r("u.csv");
  std::vector<double> t(gyro.size());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) * dt;
  if (ref.empty()) ref.assign(gyro.size(), 0.0);
  r.set_column("t_s", t);
  r.set_column("ref_rate_dps", ref);
  r.set_column("gyro_dps", gyro);
  return r;
}

DecimationRequest factor(int b) { return DecimationRequest::parse(std::to_string(b), "--decimate"); }

double variance(const std::vector<double>& v) {
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return s / static_cast<double>(v.size() - 1);
}

TEST(Decimation, BlockMeansAreIntervalMeansAndNeverSpanAGap) {
  // 0.1-s samples 0..9, a gap of 1 s, then 10..16; blocks of 3: {0,1,2} {3,4,5} {6,7,8}, 9 dropped before the
  // gap; {10,11,12} {13,14,15}, 16 dropped at the end.
  Recording r("g.csv");
  std::vector<double> t, gyro, ref, temp;
  for (int i = 0; i < 17; ++i) {
    t.push_back(0.1 * i + (i >= 10 ? 1.0 : 0.0));
    gyro.push_back(i * i);
    ref.push_back(i % 2 ? 2.0 : -2.0);  // within a block of 3: sd sqrt(8/9) * 2, range 4
    temp.push_back(20.0 + 0.5 * i);
  }
  r.set_column("t_s", t), r.set_column("ref_rate_dps", ref), r.set_column("gyro_dps", gyro), r.set_column("temp_c", temp);
  r.set_meta("sample_rate_hz", "10");
  const DecimatedRecording d = decimate(r, factor(3), {"ref_rate_dps", "temp_c"});
  const auto& g = d.recording.column("gyro_dps");
  ASSERT_EQ(g.size(), 5u);
  EXPECT_DOUBLE_EQ(g[0], (0 + 1 + 4) / 3.0);
  EXPECT_DOUBLE_EQ(g[2], (36 + 49 + 64) / 3.0);
  EXPECT_DOUBLE_EQ(g[3], (100 + 121 + 144) / 3.0);
  EXPECT_DOUBLE_EQ(d.recording.column("t_s")[3], (2.0 + 2.1 + 2.2) / 3.0);
  EXPECT_EQ(d.decimation.factor, 3);
  EXPECT_EQ(d.decimation.rows_in, 17u);
  EXPECT_EQ(d.decimation.dropped, 2u);
  EXPECT_EQ(d.decimation.breaks, 1u);
  EXPECT_NEAR(d.decimation.interval_in_s, 0.1, 1e-12);
  EXPECT_NEAR(d.decimation.interval_out_s, 0.3, 1e-12);
  EXPECT_EQ(d.recording.meta("sample_rate_hz").value(), format_number(1.0 / d.decimation.interval_out_s));
  const InputSpread* rate = d.decimation.spread("ref_rate_dps");
  ASSERT_NE(rate, nullptr);
  EXPECT_NEAR(rate->max_sd, 2.0 * std::sqrt(8.0 / 9.0), 1e-12);
  EXPECT_DOUBLE_EQ(rate->max_range, 4.0);
  EXPECT_NEAR(d.decimation.spread("temp_c")->max_sd, 0.5 * std::sqrt(2.0 / 3.0), 1e-12);  // 0, 0.5, 1 about their mean
  EXPECT_EQ(rate->sd.size(), 5u);
  const std::string s = d.decimation.statement();
  EXPECT_THAT(s, HasSubstr("block means of 3 samples, interval 0.1 -> 0.3 s, 17 -> 5 samples"));
  EXPECT_THAT(s, HasSubstr("2 in incomplete blocks before 1 gap(s) and at the end left out"));
  EXPECT_THAT(s, HasSubstr("ref_rate_dps 1.89 deg/s (range 4)"));
}

TEST(Decimation, APositionChangeEndsABlock) {
  Recording r = uniform({1, 2, 3, 4, 5, 6}, 1.0);
  r.set_column("position_id", {1, 1, 2, 2, 2, 2});
  const DecimatedRecording d = decimate(r, factor(2), {});
  EXPECT_EQ(d.recording.column("position_id"), (std::vector<double>{1, 2, 2}));
  EXPECT_EQ(d.recording.column("gyro_dps"), (std::vector<double>{1.5, 3.5, 5.5}));
}

// The continuous-time processes sampled at b dt: white noise's per-sample variance falls by b; a random walk's
// interval means step with a variance b times larger (2/3 q T for intervals of length T).
TEST(Decimation, NoiseProcessesAreTheSameProcessesAtTheLongerInterval) {
  RandomStream rng(5, "decimation test");
  const std::size_t n = 400000;
  const int b = 8, sub = 16;  // the random walk integrated in 16 steps per sample, each sample its interval's mean
  std::vector<double> white(n), walk(n);
  double w = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    white[i] = rng.normal();
    double mean = 0.0;
    for (int k = 0; k < sub; ++k) w += rng.normal() / std::sqrt(static_cast<double>(sub)), mean += w / sub;
    walk[i] = mean;
  }
  const DecimatedRecording dw = decimate(uniform(white, 1.0), factor(b), {});
  EXPECT_NEAR(variance(dw.recording.column("gyro_dps")) * b, 1.0, 0.03);
  std::vector<double> steps, block_steps;
  for (std::size_t i = 1; i < n; ++i) steps.push_back(walk[i] - walk[i - 1]);
  const DecimatedRecording dm = decimate(uniform(walk, 1.0), factor(b), {});  // held: column() refers into it
  const std::vector<double>& m = dm.recording.column("gyro_dps");
  for (std::size_t i = 1; i < m.size(); ++i) block_steps.push_back(m[i] - m[i - 1]);
  EXPECT_NEAR(variance(block_steps) / variance(steps), b, 0.05 * b);
}

TEST(Decimation, TheAutomaticFactorKeepsAtMostTheTarget) {
  DecimationRequest a;
  a.target_rows = 1000;
  EXPECT_EQ(a.factor_for(999), 1);
  EXPECT_EQ(a.factor_for(1000), 1);
  EXPECT_EQ(a.factor_for(1001), 2);
  EXPECT_EQ(a.factor_for(10000000), 10000);
  EXPECT_EQ(DecimationRequest::parse("none", "--decimate").factor_for(10000000), 1);
  EXPECT_EQ(factor(7).factor_for(10), 7);
  EXPECT_THAT(testing_support::error_of([] { DecimationRequest::parse("0", "--decimate"); }), HasSubstr("--decimate: '0' is not auto, none"));
  EXPECT_THAT(testing_support::error_of([] { DecimationRequest::parse("4x", "--decimate"); }), HasSubstr("'4x'"));
  // Factor 1 is the recording as it was.
  const Recording r = uniform({1, 2, 3}, 0.5);
  const DecimatedRecording same = decimate(r, DecimationRequest::parse("none", "--decimate"), {"ref_rate_dps"});
  EXPECT_FALSE(same.decimation.applied());
  EXPECT_EQ(same.recording.column("gyro_dps"), r.column("gyro_dps"));
}

TEST(Decimation, AFileReadWithBlockMeansEqualsTheRecordingDecimatedInMemory) {
  RandomStream rng(9, "decimation file");
  std::vector<double> gyro(5003), ref(5003);
  for (std::size_t i = 0; i < gyro.size(); ++i) ref[i] = 10.0 * std::sin(0.01 * static_cast<double>(i)), gyro[i] = ref[i] + rng.normal();
  Recording r = uniform(gyro, 0.01, ref);
  const auto path = std::filesystem::temp_directory_path() / ("gyrosid_decimation_" + std::to_string(::getpid()) + ".csv");
  write_recording(r, path);
  DecimationRequest automatic;
  automatic.target_rows = 1000;  // 5003 rows: b = 6
  const DecimatedRecording streamed = read_decimated(path, automatic, {"ref_rate_dps"}, {"t_s", "gyro_dps", "ref_rate_dps"});
  const DecimatedRecording in_memory = decimate(read_recording(path), automatic, {"ref_rate_dps"});
  std::filesystem::remove(path);
  EXPECT_EQ(streamed.decimation.factor, 6);
  EXPECT_EQ(streamed.recording.rows(), 833u);
  for (const char* c : {"t_s", "gyro_dps", "ref_rate_dps"}) EXPECT_EQ(streamed.recording.column(c), in_memory.recording.column(c)) << c;
  EXPECT_EQ(streamed.decimation.spread("ref_rate_dps")->sd, in_memory.decimation.spread("ref_rate_dps")->sd);
  EXPECT_EQ(streamed.decimation.dropped, 5u);
}

}  // namespace
}  // namespace gyrosid
