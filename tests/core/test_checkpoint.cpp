// The kill-safe checkpoint: what is saved comes back exactly, a checkpoint of another computation is refused,
// and a finished one leaves nothing behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include <unistd.h>

#include "core/checkpoint.h"
#include "core/error.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;

class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = fs::temp_directory_path() / ("gyrosid_checkpoint_test_" + std::to_string(getpid())) / ".x_checkpoint.json";
    fs::remove_all(file_.parent_path());
  }
  void TearDown() override { fs::remove_all(file_.parent_path()); }
  fs::path file_;
};

TEST_F(CheckpointTest, SavedSeriesAndRecordsComeBackBitForBit) {
  // Values whose shortest decimal needs all 17 digits, and a non-finite value inside a record's array.
  const std::vector<double> series{0.1 + 0.2, 1.0 / 3.0, -2.2250738585072014e-308, 6.02214076e23};
  {
    Checkpoint c(file_, "abc", false);
    c.save("runs", series);
    c.save_record("stage", {{"history", {1.5, std::numeric_limits<double>::infinity(), 2.5}}, {"best", 1.0 / 7.0}, {"note", "done"}});
  }
  const Checkpoint resumed(file_, "abc", true);
  ASSERT_EQ(resumed.series("runs").size(), series.size());
  for (std::size_t i = 0; i < series.size(); ++i) EXPECT_EQ(resumed.series("runs")[i], series[i]) << i;  // exact
  EXPECT_EQ(resumed.record("stage").at("best").get<double>(), 1.0 / 7.0);
  EXPECT_EQ(resumed.record("stage").at("note"), "done");
  const std::vector<double> history = saved_numbers(resumed.record("stage").at("history"));
  ASSERT_EQ(history.size(), 3u);
  EXPECT_EQ(history[0], 1.5);
  EXPECT_TRUE(std::isnan(history[1]));  // JSON has no infinity: saved as null, read as NaN
  EXPECT_EQ(history[2], 2.5);
  EXPECT_TRUE(resumed.series("never").empty());
  EXPECT_TRUE(resumed.record("never").is_null());
}

TEST_F(CheckpointTest, AnotherComputationsCheckpointIsRefusedAndAFreshStartIgnoresIt) {
  Checkpoint(file_, "abc", false).save("runs", {1.0});
  EXPECT_THROW(Checkpoint(file_, "other", true), Error);
  const Checkpoint fresh(file_, "other", false);  // without resume: starts afresh
  EXPECT_TRUE(fresh.series("runs").empty());
  Checkpoint done(file_, "abc", true);
  EXPECT_EQ(done.series("runs"), std::vector<double>{1.0});
  done.finish();
  EXPECT_FALSE(fs::exists(file_));
  const Checkpoint disabled;
  EXPECT_FALSE(disabled.enabled());
}

}  // namespace
}  // namespace gyrosid
