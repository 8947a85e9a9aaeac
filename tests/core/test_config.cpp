#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
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

// Found by fuzzing: a position of 6e101 was cast to int (undefined behaviour). Integers are whole and within
// int's range, or a located error.
TEST(Config, IntegersAreWholeAndInRange) {
  const ConfigNode c = ConfigNode::parse("n: 7\nlist: [1, -6]\nbig: 2147483648\nhuge: [1, 6e101]\nfrac: 2.5\n", "i.yaml");
  EXPECT_EQ(c.integer("n"), 7);
  EXPECT_EQ(c.integer("absent", 3), 3);
  EXPECT_EQ(c.integers("list", {}), (std::vector<int>{1, -6}));
  EXPECT_EQ(c.integers("absent", {4, 5}), (std::vector<int>{4, 5}));
  EXPECT_THAT(error_of([&] { c.integer("big"); }), HasSubstr("i.yaml:3"));
  EXPECT_THAT(error_of([&] { c.integers("huge", {}); }), HasSubstr("huge[1]"));
  EXPECT_THAT(error_of([&] { c.integer("frac"); }), HasSubstr("'2.5'"));
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

// Found by fuzzing: keys that are maps or lists, repeated keys and alias bombs are located errors, not
// yaml-cpp exceptions escaping the readers.
TEST(Config, ComplexRepeatedAndExplodingKeysAreLocatedErrors) {
  auto message = [](const std::string& text) { return testing_support::error_of([&] { ConfigNode::parse(text, "c.yaml"); }); };
  EXPECT_THAT(message("? [a, b]\n: 1\n"), ::testing::HasSubstr("c.yaml:1:3: a key must be a plain name"));
  EXPECT_THAT(message("a: 1\nb: 2\na: 3\n"), ::testing::HasSubstr("c.yaml:3:1: key 'a' appears twice"));
  std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k < 8; ++k) {
    bomb += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [";
    for (int j = 0; j < 10; ++j) bomb += std::string(j ? ", " : "") + "*a" + std::to_string(k - 1);
    bomb += "]\n";
  }
  EXPECT_THAT(message(bomb), ::testing::HasSubstr("more than a million nodes"));
  EXPECT_EQ(ConfigNode::parse("a: 1\nb: {c: 2}\n", "ok.yaml").keys(), (std::vector<std::string>{"a", "b"}));
}

// Lists given on the command line ("--features measured_rate, temperature"): items without the blanks around
// them, empty items dropped, and join's inverse.
TEST(Config, ListsSplitIntoTheirTrimmedItems) {
  EXPECT_EQ(split_list(" measured_rate ,temperature,, accel_x_mps2 "), (std::vector<std::string>{"measured_rate", "temperature", "accel_x_mps2"}));
  EXPECT_EQ(split_list("short,medium"), split_list(join({"short", "medium"}, ",")));
  EXPECT_TRUE(split_list(" , ").empty());
  EXPECT_EQ(split_list("a b;c", ';'), (std::vector<std::string>{"a b", "c"}));
  // Help text's lists (registries' names): "a, b or c".
  EXPECT_EQ(join({"nlopt", "ipopt", "compass"}, ", ", " or "), "nlopt, ipopt or compass");
  EXPECT_EQ(join({"nlopt", "ipopt"}, ", ", " or "), "nlopt or ipopt");
  EXPECT_EQ(join({"nlopt"}, ", ", " or "), "nlopt");
  EXPECT_EQ(join({}, ", ", " or "), "");
}

// A list of numbers written as text reads back bit for bit (format_number's shortest round trip, each item).
TEST(Config, NumberListsReadBackExactly) {
  const std::vector<double> values{-20.0, 0.1, 1.0 / 3.0, 1e-7, -123456.789};
  std::vector<double> back;
  for (const auto& item : split_list(format_numbers(values, ","))) back.push_back(std::stod(item));
  EXPECT_EQ(back, values);
  EXPECT_EQ(split_list(format_numbers(values)).size(), values.size());  // ", " between them, trimmed away
  EXPECT_EQ(format_numbers({}), "");
}

}  // namespace
}  // namespace gyrosid
