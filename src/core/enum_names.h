// Enum <-> string round trip for every pluggable choice (solvers, trajectories, effects, kernels, ...).
// A type opts in by specialising EnumNames<E> with a table of {value, name} and a noun:
//
//   template <> struct EnumNames<OutsidePolicy> {
//     static constexpr std::string_view kNoun = "outside-grid policy";
//     static constexpr std::array<std::pair<OutsidePolicy, std::string_view>, 2> kTable{{...}};
//   };
//
// An unknown name is an Error that lists the known ones.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "core/error.h"

namespace gyrosid {

template <typename E>
struct EnumNames;

template <typename E>
std::string_view to_string(E value) {
  for (const auto& [v, name] : EnumNames<E>::kTable) {
    if (v == value) return name;
  }
  return "?";
}

template <typename E>
std::string known_names() {
  std::string out;
  for (const auto& [v, name] : EnumNames<E>::kTable) {
    if (!out.empty()) out += ", ";
    out += name;
  }
  return out;
}

// `where` prefixes the message, e.g. "configs/x.yaml:4 (scale_factor.outside)".
template <typename E>
E parse_enum(std::string_view text, std::string_view where = "") {
  for (const auto& [v, name] : EnumNames<E>::kTable) {
    if (name == text) return v;
  }
  fail(where, where.empty() ? "" : ": ", "unknown ", EnumNames<E>::kNoun, " '", text, "'; known: ",
       known_names<E>());
}

}  // namespace gyrosid
