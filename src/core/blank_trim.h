// Cell and line trimming shared by the text readers (recordings, IMU text logs).
#pragma once

#include <string_view>

namespace gyrosid {

// `s` without leading spaces and tabs and without trailing spaces, tabs and a CR (a CRLF file's line end).
inline std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

}  // namespace gyrosid
