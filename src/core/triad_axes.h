// The names of a triad's three gyro axes, in the order of every triad vector and matrix (x, y, z).
#pragma once

#include <array>

namespace gyrosid {

inline constexpr std::array<const char*, 3> kTriadAxes{"x", "y", "z"};

}  // namespace gyrosid
