// gyrosid's one exception type and a small message builder (GCC 12 has no <format>).
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace gyrosid {

// Every user-facing failure (bad file, bad key, bad option, impossible request) is an Error whose message
// names where it happened: file and line, config key, or command-line option.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// str_cat("line ", 12, ": bad value ", 3.5) -> "line 12: bad value 3.5" (doubles at full precision).
template <typename... Args>
std::string str_cat(Args&&... args) {
  std::ostringstream out;
  out.precision(12);
  (out << ... << std::forward<Args>(args));
  return out.str();
}

template <typename... Args>
[[noreturn]] void fail(Args&&... args) {
  throw Error(str_cat(std::forward<Args>(args)...));
}

}  // namespace gyrosid
