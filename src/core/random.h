// Seeded random streams. Every random quantity in gyrosid comes from a RandomStream named after what it
// drives ("gyro_x/arw", "mc/run17/gyro_y/gm", ...), so a seed and a name fix the numbers bit for bit on
// every platform, and adding a new noise term never changes the draws of the existing ones.
//
// Generator: xoshiro256++ (Blackman & Vigna 2019), state filled by SplitMix64 from seed and the FNV-1a hash
// of the stream name. Normal deviates: Marsaglia's polar method (exact, no tables).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace gyrosid {

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::string_view stream_name);

  std::uint64_t next_u64();
  double uniform();        // in (0, 1), never exactly 0 or 1
  double normal();         // N(0, 1)
  double normal(double mean, double sigma) { return mean + sigma * normal(); }

 private:
  std::array<std::uint64_t, 4> s_{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Stable 64-bit hash of a name (FNV-1a), used to derive stream seeds.
std::uint64_t hash_name(std::string_view name);

}  // namespace gyrosid
