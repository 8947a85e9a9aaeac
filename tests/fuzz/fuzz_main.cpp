// libFuzzer entry point of one target; GYROSID_FUZZ_TARGET names it at compile time (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const gyrosid::fuzz::Target& target = gyrosid::fuzz::target(GYROSID_FUZZ_TARGET);
  gyrosid::fuzz::run_one(target, std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
