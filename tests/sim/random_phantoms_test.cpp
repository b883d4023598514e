// The random phantoms (sim/random_phantoms.h) and their generator (sim/splitmix64.h): blobs and
// random voxels reproducible for a seed, their parameters and statistics, blobs with handles at
// the default threshold, and values that must not change on any platform.
#include "random_phantoms.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "phantom_factory.h"
#include "phantom_measures.h"
#include "splitmix64.h"

namespace mvox::sim {
namespace {

using test::count_at_least;
using test::count_components;
using test::euler_characteristic;
using test::index_of;

// ---------------------------------------------------------------------------------------------
// Random blobs

TEST(BlobsTest, ReproducibleForASeedAndDifferentForAnother) {
  const Grid g{32, 24, 20};
  EXPECT_EQ(sample_volume(RandomBlobs(g, 42, 8)), sample_volume(RandomBlobs(g, 42, 8)));
  EXPECT_NE(sample_volume(RandomBlobs(g, 42, 8)), sample_volume(RandomBlobs(g, 43, 8)));
}

TEST(BlobsTest, ParametersInTheirRanges) {
  const RandomBlobs blobs({64, 64, 64}, 7, 12);
  ASSERT_EQ(blobs.blobs().size(), 12u);
  for (const Blob& b : blobs.blobs()) {
    for (double c : {b.centre.x, b.centre.y, b.centre.z}) {
      EXPECT_GE(c, 0.1 * 63);
      EXPECT_LE(c, 0.9 * 63);
    }
    EXPECT_GE(b.radius, 2);
    EXPECT_LE(b.radius, 6.4);  // a tenth of 64
    EXPECT_GE(b.amplitude, 0.6);
    EXPECT_LT(b.amplitude, 1.4);
  }
}

TEST(BlobsTest, DensityIsTheSumOfGaussians) {
  const RandomBlobs blobs({40, 40, 40}, 3, 5);
  for (const Blob& b : blobs.blobs()) {
    const auto x = static_cast<std::uint32_t>(std::lround(b.centre.x));
    const auto y = static_cast<std::uint32_t>(std::lround(b.centre.y));
    const auto z = static_cast<std::uint32_t>(std::lround(b.centre.z));
    double expected = 0;
    for (const Blob& o : blobs.blobs()) {
      const double d2 =
          std::pow(x - o.centre.x, 2) + std::pow(y - o.centre.y, 2) + std::pow(z - o.centre.z, 2);
      expected += o.amplitude * std::pow(0.5, d2 / (o.radius * o.radius));
    }
    EXPECT_NEAR(blobs.density(x, y, z), expected, 1e-5);
  }
}

TEST(BlobsTest, DefaultThresholdGivesSeveralComponentsWithHandles) {
  const Grid g{64, 64, 64};
  const auto t = static_cast<float>(default_density_threshold("blobs"));
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<float> volume = sample_volume(*make_phantom("blobs", g, seed));
    const int components = count_components(g, volume, t);
    EXPECT_GE(components, 3) << "seed " << seed;
    // chi = components - tunnels + cavities, so chi < components proves a tunnel (a handle).
    EXPECT_LT(euler_characteristic(g, volume, t), components) << "seed " << seed;
    EXPECT_GT(count_at_least(volume, t), 10000u) << "seed " << seed;
  }
}

// ---------------------------------------------------------------------------------------------
// Random voxels

TEST(RandomVoxelsTest, ReproducibleForASeedAndDifferentForAnother) {
  const Grid g{32, 32, 32};
  EXPECT_EQ(sample_volume(RandomVoxels(g, 5, 0.3)), sample_volume(RandomVoxels(g, 5, 0.3)));
  EXPECT_NE(sample_volume(RandomVoxels(g, 5, 0.3)), sample_volume(RandomVoxels(g, 6, 0.3)));
}

TEST(RandomVoxelsTest, FractionWithinTwoPercentOfProbability) {
  const Grid g{64, 64, 64};
  for (double p : {0.1, 0.3, 0.5, 0.9}) {
    const std::vector<float> volume = sample_volume(RandomVoxels(g, 11, p));
    const double fraction = static_cast<double>(count_at_least(volume, 0.5f)) / volume.size();
    EXPECT_NEAR(fraction, p, 0.02 * p) << "p = " << p;
  }
  EXPECT_EQ(count_at_least(sample_volume(RandomVoxels({16, 16, 16}, 1, 0.0)), 0.5f), 0u);
  EXPECT_EQ(count_at_least(sample_volume(RandomVoxels({16, 16, 16}, 1, 1.0)), 0.5f), 4096u);
}

TEST(RandomVoxelsTest, VoxelDependsOnlyOnSeedAndPosition) {
  const RandomVoxels small({16, 16, 16}, 9, 0.3);
  const RandomVoxels large({20, 18, 40}, 9, 0.3);
  for (std::uint32_t z = 0; z < 16; ++z)
    for (std::uint32_t y = 0; y < 16; ++y)
      for (std::uint32_t x = 0; x < 16; ++x)
        ASSERT_EQ(small.density(x, y, z), large.density(x, y, z));
}

TEST(RandomVoxelsTest, NeighbouringVoxelsAreUncorrelated) {
  // A weak hash would make x and x+1 agree more (or less) often than p^2 + (1-p)^2.
  const Grid g{64, 64, 64};
  const double p = 0.3;
  const std::vector<float> v = sample_volume(RandomVoxels(g, 13, p));
  std::size_t pairs = 0, equal_x = 0, equal_y = 0, equal_z = 0;
  for (std::uint32_t z = 0; z + 1 < 64; ++z)
    for (std::uint32_t y = 0; y + 1 < 64; ++y)
      for (std::uint32_t x = 0; x + 1 < 64; ++x) {
        const float d = v[index_of(g, x, y, z)];
        ++pairs;
        equal_x += d == v[index_of(g, x + 1, y, z)];
        equal_y += d == v[index_of(g, x, y + 1, z)];
        equal_z += d == v[index_of(g, x, y, z + 1)];
      }
  const double expected = p * p + (1 - p) * (1 - p);
  EXPECT_NEAR(static_cast<double>(equal_x) / pairs, expected, 0.01);
  EXPECT_NEAR(static_cast<double>(equal_y) / pairs, expected, 0.01);
  EXPECT_NEAR(static_cast<double>(equal_z) / pairs, expected, 0.01);
}

TEST(RandomVoxelsTest, RejectsBadProbability) {
  EXPECT_THROW(RandomVoxels({8, 8, 8}, 1, -0.1), std::invalid_argument);
  EXPECT_THROW(RandomVoxels({8, 8, 8}, 1, 1.5), std::invalid_argument);
  EXPECT_THROW(RandomVoxels({8, 8, 8}, 1, std::nan("")), std::invalid_argument);
}

// Portability anchors: these values must not change on any platform or compiler.
TEST(RandomTest, SplitMix64MatchesTheReferenceSequence) {
  // First outputs of Vigna's splitmix64.c seeded with 1234567.
  std::uint64_t state = 1234567;
  EXPECT_EQ(splitmix64_next(state), 6457827717110365317u);
  EXPECT_EQ(splitmix64_next(state), 3203168211198807973u);
  EXPECT_EQ(splitmix64_next(state), 9817491932198370423u);
  EXPECT_EQ(unit_interval(0), 0.0);
  EXPECT_LT(unit_interval(~std::uint64_t{0}), 1.0);
  EXPECT_EQ(unit_interval(std::uint64_t{1} << 63), 0.5);
}

TEST(RandomTest, GoldenRandomVoxelCount) {
  const std::vector<float> volume = sample_volume(RandomVoxels({32, 32, 32}, 1, 0.3));
  EXPECT_EQ(count_at_least(volume, 0.5f), 9810u);  // also computed by an independent script
}

}  // namespace
}  // namespace mvox::sim
