// Every input a fuzzer once crashed a reader with (tests/fuzz/regressions/<target>/), and every seed, replayed
// in the ordinary build: each must be read or refused with a gyrosid::Error - never crash, never throw
// anything else. A crash found by scripts/fuzz.sh is fixed and its input added here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fuzz_targets.h"

namespace gyrosid::fuzz {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class FuzzRegressions : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzRegressions, EveryRecordedInputIsReadOrRefused) {
  const fs::path dir = fs::path(GYROSID_SOURCE_DIR) / "tests" / "fuzz" / "regressions" / GetParam();
  int inputs = 0;
  if (fs::exists(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      EXPECT_NO_THROW(run_one(target(GetParam()), read_bytes(entry.path()))) << entry.path();
      ++inputs;
    }
  }
  RecordProperty("inputs", inputs);
}

TEST(FuzzTargets, SeedsParseWithoutError) {
  // The seeds are valid inputs: each target reads them without even an Error (so the corpus starts inside
  // the readers, not at their first check).
  const fs::path seeds = fs::path(GYROSID_SOURCE_DIR) / "tests" / "fuzz" / "seeds";
  for (const auto& t : targets()) {
    if (!fs::exists(seeds / t.name)) continue;
    for (const auto& entry : fs::directory_iterator(seeds / t.name)) {
      EXPECT_NO_THROW(t.run(read_bytes(entry.path()))) << t.name << ": " << entry.path();
    }
  }
}

std::vector<std::string> target_names() {
  std::vector<std::string> names;
  for (const auto& t : targets()) names.push_back(t.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(EveryTarget, FuzzRegressions, ::testing::ValuesIn(target_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace gyrosid::fuzz
