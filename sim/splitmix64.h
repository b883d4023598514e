#pragma once
// Portable random numbers for the phantoms: SplitMix64 (Steele, Lea and Flood, "Fast splittable
// pseudorandom number generators", OOPSLA 2014; constants from Vigna's reference splitmix64.c).
// Only 64-bit integer arithmetic, so a seed gives the same phantom on every platform and
// compiler; std::uniform_real_distribution is avoided because its output is
// implementation-defined.
#include <cstdint>

namespace mvox::sim {

constexpr std::uint64_t kSplitMix64Gamma = 0x9e3779b97f4a7c15u;

// The SplitMix64 output function: a bijective avalanche mix of one 64-bit word.
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

// The next output of the SplitMix64 sequence whose state is `state` (advanced in place).
constexpr std::uint64_t splitmix64_next(std::uint64_t& state) {
  state += kSplitMix64Gamma;
  return splitmix64_mix(state);
}

// A hash of (seed, x, y, z): each coordinate is folded in through a full mix so that
// neighbouring voxels and neighbouring seeds give unrelated values.
constexpr std::uint64_t voxel_hash(std::uint64_t seed, std::uint32_t x, std::uint32_t y,
                                   std::uint32_t z) {
  std::uint64_t h = splitmix64_mix(seed + kSplitMix64Gamma);
  h = splitmix64_mix(h ^ (x + kSplitMix64Gamma));
  h = splitmix64_mix(h ^ (y + 2 * kSplitMix64Gamma));
  return splitmix64_mix(h ^ (z + 3 * kSplitMix64Gamma));
}

// The top 53 bits as a double in [0, 1): exact, every value a multiple of 2^-53.
constexpr double unit_interval(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace mvox::sim
