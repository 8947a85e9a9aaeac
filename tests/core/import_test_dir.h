// A scratch directory per test (and process: ctest runs a fixture's tests in parallel processes) for the
// importers' tests: logs written into it, the import's recording read back from it.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "core/imu_import.h"
#include "core/recording.h"

namespace gyrosid::testing_support {

class ImportTest : public ::testing::Test {
 protected:
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }
  // Imports into out.csv and reads the recording back through the recording format's own reader.
  Recording import(const ImuImportOptions& o) {
    result_ = import_imu_log(o, out());
    return read_recording(out());
  }
  std::filesystem::path out() const { return dir_ / "out.csv"; }
  std::string out_text() const {
    std::ifstream in(out(), std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // The line of the written recording that follows the header line (data row `row`, 0-based).
  std::string data_line(std::size_t row) const {
    std::istringstream in(out_text());
    std::string line;
    while (std::getline(in, line) && line.rfind("t_s,", 0) != 0) {
    }
    for (std::size_t r = 0; r <= row && std::getline(in, line);) ++r;
    return line;
  }
  std::filesystem::path dir_ = std::filesystem::temp_directory_path() /
                               ("gyrosid_import_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                                std::to_string(getpid()));
  ImportResult result_;
};

}  // namespace gyrosid::testing_support
