// PASS 3's per-word cube configurations (word_configs.h) against their definition: bit c of
// cube cx's configuration is bit cx of corner word c. Checks whichever path the build has: SSE2
// on x86-64, NEON on aarch64, the portable loop elsewhere.
#include "word_configs.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace mvox {
namespace {

TEST(WordConfigs, EveryCubeOfRandomAndSparseWords) {
  std::mt19937_64 random(3);
  for (int trial = 0; trial < 2000; ++trial) {
    std::uint64_t corners[8];
    for (std::uint64_t& corner : corners) {
      corner = random();
      if (trial % 3 == 1) corner &= random() & random();  // sparse
      if (trial % 3 == 2) corner |= random() | random();  // dense
    }
    const WordConfigs configs(corners);
    for (int cx = 0; cx < 64; ++cx) {
      unsigned expected = 0;
      for (int c = 0; c < 8; ++c) expected |= static_cast<unsigned>(corners[c] >> cx & 1) << c;
      ASSERT_EQ(configs[cx], expected) << "trial " << trial << " cube " << cx;
    }
  }
}

TEST(WordConfigs, EachCornerAlone) {
  for (int c = 0; c < 8; ++c)
    for (int cx = 0; cx < 64; ++cx) {
      std::uint64_t corners[8] = {};
      corners[c] = std::uint64_t{1} << cx;
      const WordConfigs configs(corners);
      for (int other = 0; other < 64; ++other)
        ASSERT_EQ(configs[other], other == cx ? 1u << c : 0u) << c << " " << cx << " " << other;
    }
}

}  // namespace
}  // namespace mvox
