// gyrosid's version and the source commit it was configured from (for provenance in reports).
#pragma once

#include <string>

namespace gyrosid {

std::string version_string();  // "0.1.0 (git 1a2b3c4)" - the commit as of the last CMake configure

}  // namespace gyrosid
