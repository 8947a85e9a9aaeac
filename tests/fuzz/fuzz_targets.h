// The entry points fuzzed by libFuzzer (tests/fuzz/fuzz_main.cpp) and replayed by the regression test
// (tests/fuzz/test_fuzz_regressions.cpp): every reader of outside input, fed arbitrary bytes. A reader may
// refuse its input with a gyrosid::Error (that is its job); any other exception, a crash, a sanitizer report,
// a hang or an unbounded allocation is a bug.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace gyrosid::fuzz {

struct Target {
  std::string name;                         // fuzz_<name> executable, tests/fuzz/regressions/<name>/
  std::vector<std::string> seed_globs;      // seed corpus, relative to the repository
  std::function<void(std::string_view)> run;
};

const std::vector<Target>& targets();
const Target& target(std::string_view name);

// Runs a target on one input, swallowing the gyrosid::Error a reader is allowed to throw.
void run_one(const Target& target, std::string_view input);

}  // namespace gyrosid::fuzz
