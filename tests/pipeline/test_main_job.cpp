// The main job called in-process (pipeline/main_job.h): the same numbers as the `gyrosid run` command on
// the same options and seed, and the thesis's ordering of the two calibrations.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "pipeline/main_job.h"
#include "error_of.h"
#include "read_file.h"

namespace gyrosid {
namespace {

namespace fs = std::filesystem;

using testing_support::read_json;

TEST(MainJob, InProcessEqualsTheCommandAndRanksTheRbfFirst) {
  const fs::path dir = fs::temp_directory_path() / "gyrosid_main_job_in_process";
  fs::remove_all(dir);
  MainJobOptions o;
  o.out = dir / "library";
  o.flights = {"short"};
  o.rbf_config = "builtin:calibration/rbf_noisy.yaml";
  std::vector<int> steps;
  o.on_step = [&](int step, int total, const std::string&) {
    steps.push_back(step);
    EXPECT_EQ(total, 7);
  };
  const MainJobResult r = run_main_job(o);
  EXPECT_EQ(steps, (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(r.flights.size(), 1u);
  const double classical = nav::score_m(r.flights[0].classical.run), rbf = nav::score_m(r.flights[0].rbf.run);
  EXPECT_GT(classical / rbf, 30.0);  // noise-free calibration data: the RBF far ahead (thesis Table 5.4)
  EXPECT_LT(r.rbf.surface.stats.rms_dph, r.classical.surface.stats.rms_dph);

  const std::string command = std::string(GYROSID_EXE) + " run --flights short --rbf-config builtin:calibration/rbf_noisy.yaml --out " +
                              (dir / "command").string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto s = read_json(dir / "command" / "summary.json");
  const auto& short_flight = s["criterion_of_fit"]["short"];
  EXPECT_EQ(short_flight["classical"]["end_error_m"].get<double>(), r.flights[0].classical.run.end_error_m);
  EXPECT_EQ(short_flight["rbf"]["end_error_m"].get<double>(), r.flights[0].rbf.run.end_error_m);
  EXPECT_EQ(s["models"]["rbf"]["surface"]["rms_dph"].get<double>(), r.rbf.surface.stats.rms_dph);
  EXPECT_EQ(s["monte_carlo_short"]["rbf"]["sigma_m"].get<double>(), r.short_monte_carlo.back().mc->sigma_m);
  fs::remove_all(dir);
}

TEST(MainJob, RefusesATriadSensorBeforeWritingAnything) {
  const fs::path dir = fs::temp_directory_path() / "gyrosid_main_job_triad";
  fs::remove_all(dir);
  MainJobOptions o;
  o.out = dir;
  o.sensor = "builtin:sensors/fog_triad.yaml";
  o.on_step = [](int, int, const std::string&) {};
  EXPECT_NE(testing_support::error_of([&] { run_main_job(o); }).find("is a triad"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace gyrosid
