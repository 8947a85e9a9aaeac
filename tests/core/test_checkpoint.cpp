// The kill-safe checkpoint: what is saved comes back exactly, a checkpoint of another computation is refused,
// and a finished one leaves nothing behind - its row spools (core/row_spool.h) included.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <unistd.h>

#include "core/checkpoint.h"
#include "core/error.h"
#include "core/row_spool.h"

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

// A spool's rows come back bit for bit by index; on resume the rows the checkpoint counted are kept and a torn
// append after them (a killed write) is cut off; rows the file does not have are refused by name.
TEST_F(CheckpointTest, ASpoolKeepsItsCountedRowsAndCutsATornAppend) {
  fs::create_directories(file_.parent_path());
  Checkpoint checkpoint(file_, "abc", false);
  const fs::path at = checkpoint.spool_file("units");
  EXPECT_EQ(at, file_.parent_path() / ".x_checkpoint.units.rows");
  const std::vector<double> rows = {1.0 / 3.0, -0.0, 1e-310, 2.0, std::numeric_limits<double>::quiet_NaN(), 6.5};
  {
    RowSpool spool(2, at, 0);
    spool.append({rows.begin(), rows.begin() + 4});
    std::ofstream(at, std::ios::app | std::ios::binary) << "torn";  // half a row a kill left
  }
  RowSpool resumed(2, at, 2);
  EXPECT_EQ(fs::file_size(at), 2 * 2 * sizeof(double));
  resumed.append({rows.begin() + 4, rows.end()});
  ASSERT_EQ(resumed.rows(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    double row[2];
    resumed.read(i, row);
    for (std::size_t j = 0; j < 2; ++j) {
      const double expected = rows[2 * i + j];
      if (std::isnan(expected)) EXPECT_TRUE(std::isnan(row[j]));
      else EXPECT_EQ(std::memcmp(&row[j], &expected, sizeof(double)), 0) << i << ' ' << j;  // -0.0 and subnormals too
    }
  }
  EXPECT_THROW(resumed.append({1.0}), Error);  // not a whole row
  double row[2];
  EXPECT_THROW(resumed.read(3, row), Error);
  try {
    RowSpool missing(2, at, 4);
    FAIL();
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(at.string()));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("run without --resume"));
  }
  RowSpool anonymous(3);
  anonymous.append({1.0, 2.0, 3.0});
  anonymous.read(0, row);
  EXPECT_EQ(row[1], 2.0);
  checkpoint.finish();
  EXPECT_FALSE(fs::exists(at));
}

}  // namespace
}  // namespace gyrosid
