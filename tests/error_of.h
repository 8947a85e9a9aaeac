// Test helper: the message of the gyrosid::Error a call throws, or "(no error)".
#pragma once

#include <functional>
#include <string>

#include "core/error.h"

namespace gyrosid::testing_support {

inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace gyrosid::testing_support
