// A toy subcommand added from the test binary alone, proving the extension point of cli/app.h: a verb is a
// registration function - its options, help and action - and one line in extend_verbs(). The test then
// runs the command's own main in-process: --help lists the verb after the library's, the verb runs, and an
// Error from its action is reported like any subcommand's ("gyrosid <verb>: error: ...", exit status 2).
//
// scale: prints a rate converted from deg/s to deg/h (core/units.h), refusing a non-finite one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/app.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid::cli {
namespace {

void register_scale(CLI::App& app, Action& action) {
  auto rate_dps = std::make_shared<double>(0.0);
  CLI::App* cmd = app.add_subcommand("scale", "toy: a rate in deg/s printed in deg/h");
  cmd->add_option("--rate-dps", *rate_dps, "Rate, deg/s")->required();
  cmd->callback([&action, rate_dps] {
    action = [rate_dps] {
      if (!std::isfinite(*rate_dps)) fail("--rate-dps ", *rate_dps, " is not a finite rate");
      std::cout << format_significant(units::radps_to_dph(units::dps_to_radps(*rate_dps)), 6) << " deg/h\n";
    };
  });
}

// The one registration line, run before gtest lists or runs the tests.
const bool scale_registered = [] {
  extend_verbs().push_back(register_scale);
  return true;
}();

struct Outcome {
  int status;
  std::string out, err;
};

Outcome run(std::vector<std::string> args) {
  args.insert(args.begin(), "gyrosid");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const int status = main(static_cast<int>(argv.size()), argv.data());
  return {status, ::testing::internal::GetCapturedStdout(), ::testing::internal::GetCapturedStderr()};
}

TEST(CliVerbs, AVerbRegisteredFromOutsideIsListedRunsAndReportsErrors) {
  const Outcome help = run({"--help"});
  EXPECT_EQ(help.status, 0);
  EXPECT_THAT(help.out, ::testing::ContainsRegex("lot +A production lot[^\n]*\n +scale +toy: a rate in deg/s printed in deg/h"));
  const Outcome ok = run({"scale", "--rate-dps", "0.25"});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_EQ(ok.out, "900 deg/h\n");  // 0.25 deg/s x 3600 s/h
  const Outcome bad = run({"scale", "--rate-dps", "nan"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_THAT(bad.err, ::testing::HasSubstr("gyrosid scale: error: --rate-dps nan is not a finite rate"));
  EXPECT_NE(run({"scale"}).status, 0);  // its required option, refused by the parser
}

}  // namespace
}  // namespace gyrosid::cli
