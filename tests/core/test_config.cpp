#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/config.h"
#include "core/error.h"
#include "error_of.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;

using testing_support::error_of;

const char* kYaml =
    "name: test\n"
    "bias:\n"
    "  constant_dph: -15\n"
    "  temperature:\n"
    "    coefficients_dph: [0, 0.1, abc]\n"
    "rates: [1, 2, 3]\n"
    "grid:\n"
    "  - [1, 2]\n"
    "  - [3, 4]\n";

TEST(Config, ReadsTypedValues) {
  const ConfigNode c = ConfigNode::parse(kYaml, "cfg.yaml");
  EXPECT_EQ(c.text("name"), "test");
  EXPECT_EQ(c["bias"].number("constant_dph"), -15.0);
  EXPECT_EQ(c.number("missing", 7.5), 7.5);
  EXPECT_EQ(c.numbers("rates"), (std::vector<double>{1, 2, 3}));
  const auto grid = c["grid"].as_matrix();
  ASSERT_EQ(grid.size(), 2u);
  EXPECT_EQ(grid[1][0], 3.0);
}

TEST(Config, ErrorsNameFileLineAndKey) {
  const ConfigNode c = ConfigNode::parse(kYaml, "cfg.yaml");
  EXPECT_THAT(error_of([&] { c["bias"].number("scale"); }), HasSubstr("cfg.yaml:3"));
  EXPECT_THAT(error_of([&] { c["bias"].number("scale"); }), HasSubstr("bias.scale"));
  // The bad list element is reported at its own line and with its index.
  const std::string bad = error_of([&] { c["bias"]["temperature"].numbers("coefficients_dph"); });
  EXPECT_THAT(bad, HasSubstr("cfg.yaml:5"));
  EXPECT_THAT(bad, HasSubstr("coefficients_dph[2]"));
  EXPECT_THAT(bad, HasSubstr("'abc'"));
}

TEST(Config, UnknownKeyListsAllowedOnes) {
  const ConfigNode c = ConfigNode::parse("bias: {constnt_dph: 1}\n", "s.yaml");
  const std::string e = error_of([&] { c["bias"].allow_only({"constant_dph", "temperature"}); });
  EXPECT_THAT(e, HasSubstr("unknown key 'constnt_dph'"));
  EXPECT_THAT(e, HasSubstr("constant_dph, temperature"));
  EXPECT_THAT(e, HasSubstr("s.yaml:1"));
}

TEST(Config, SyntaxErrorNamesLine) {
  EXPECT_THAT(error_of([] { ConfigNode::parse("a: [1, 2\nb: 3\n", "broken.yaml"); }), HasSubstr("broken.yaml:"));
}

TEST(Config, RaggedMatrixIsRejected) {
  const ConfigNode c = ConfigNode::parse("m:\n  - [1, 2]\n  - [3]\n", "m.yaml");
  EXPECT_THAT(error_of([&] { c["m"].as_matrix(); }), HasSubstr("row has 1 values"));
}

TEST(Config, BuiltinConfigsAreEmbeddedAndResolveRelativePaths) {
  const ConfigNode triad = ConfigNode::load("builtin:sensors/fog_triad.yaml");
  EXPECT_EQ(triad.text("kind"), "triad");
  EXPECT_EQ(triad.resolve("open_loop_fog.yaml"), "builtin:sensors/open_loop_fog.yaml");
  EXPECT_EQ(ConfigNode::load(triad.resolve("open_loop_fog.yaml")).text("kind"), "gyro");
  EXPECT_THAT(error_of([] { ConfigNode::load("builtin:sensors/nope.yaml"); }), HasSubstr("builtin:sensors/open_loop_fog.yaml"));
  EXPECT_THAT(error_of([] { ConfigNode::load("/nonexistent/configs/sensors/open_loop_fog.yaml"); }),
              HasSubstr("builtin:sensors/open_loop_fog.yaml"));
}

}  // namespace
}  // namespace gyrosid
