// The geometric phantoms (sim/shapes.h) against analytic oracles: sphere, torus and nested
// shells, by volume, symmetry and chosen voxels; and the Euler characteristic the other phantom
// tests rely on, on shapes of known topology.
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "phantom_factory.h"
#include "phantom_measures.h"

namespace mvox::sim {
namespace {

using test::count_at_least;
using test::euler_characteristic;

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Sphere

TEST(SphereTest, InnerCountNearBallVolume) {
  const Grid g{64, 64, 64};
  const auto sphere = make_phantom("sphere", g, 0);
  const double r = 0.4 * 64;
  const double expected = 4.0 / 3.0 * kPi * r * r * r;
  const double count = static_cast<double>(count_at_least(sample_volume(*sphere), 0.5f));
  EXPECT_NEAR(count / expected, 1.0, 0.03) << count << " voxels, ball volume " << expected;
}

TEST(SphereTest, CentredSphereIsMirrorAndAxisSymmetric) {
  const Grid g{32, 32, 32};
  const auto sphere = make_phantom("sphere", g, 0);
  for (std::uint32_t z = 0; z < 32; ++z)
    for (std::uint32_t y = 0; y < 32; ++y)
      for (std::uint32_t x = 0; x < 32; ++x) {
        const float d = sphere->density(x, y, z);
        ASSERT_EQ(d, sphere->density(31 - x, y, z));
        ASSERT_EQ(d, sphere->density(x, 31 - y, z));
        ASSERT_EQ(d, sphere->density(x, y, 31 - z));
        ASSERT_EQ(d, sphere->density(y, x, z));
        ASSERT_EQ(d, sphere->density(z, y, x));
      }
}

TEST(SphereTest, CentreAndEdgeVoxels) {
  const Sphere sphere({21, 21, 21}, {10, 10, 10}, 5);
  EXPECT_EQ(sphere.density(10, 10, 10), 1.0f);
  EXPECT_EQ(sphere.density(15, 10, 10), 1.0f);  // distance exactly 5: boundary is inside
  EXPECT_EQ(sphere.density(16, 10, 10), 0.0f);
  EXPECT_EQ(sphere.density(10, 5, 10), 1.0f);
  EXPECT_EQ(sphere.density(10, 10, 4), 0.0f);
  EXPECT_EQ(sphere.density(14, 13, 10), 1.0f);  // sqrt(16 + 9) = 5
  EXPECT_EQ(sphere.density(14, 14, 10), 0.0f);  // sqrt(32) > 5
  EXPECT_EQ(sphere.density(0, 0, 0), 0.0f);
  EXPECT_EQ(sphere.density(20, 20, 20), 0.0f);
  EXPECT_STREQ(sphere.name(), "sphere");
}

TEST(SphereTest, RejectsBadArguments) {
  EXPECT_THROW(Sphere({8, 8, 8}, {4, 4, 4}, -1), std::invalid_argument);
  EXPECT_THROW(Sphere({8, 8, 8}, {4, 4, 4}, std::nan("")), std::invalid_argument);
  EXPECT_THROW(Sphere({8, 0, 8}, {4, 4, 4}, 2), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Torus

TEST(TorusTest, HoleIsEmptyAndTubeIsFull) {
  // Centre (31.5, 31.5, 15.5), major radius 19.2, minor radius 7.68.
  const auto torus = make_phantom("torus", {64, 64, 32}, 0);
  EXPECT_EQ(torus->density(31, 31, 15), 0.0f);
  EXPECT_EQ(torus->density(32, 32, 16), 0.0f);
  EXPECT_EQ(torus->density(51, 31, 15), 1.0f);  // on the ring, +x
  EXPECT_EQ(torus->density(12, 31, 15), 1.0f);  // -x
  EXPECT_EQ(torus->density(31, 51, 15), 1.0f);  // +y
  EXPECT_EQ(torus->density(51, 31, 23), 1.0f);  // 7.5 above the ring, inside the tube
  EXPECT_EQ(torus->density(51, 31, 25), 0.0f);  // 9.5 above: outside
  EXPECT_EQ(torus->density(51, 31, 6), 0.0f);
  EXPECT_EQ(torus->density(63, 31, 15), 0.0f);
}

TEST(TorusTest, InnerCountNearTorusVolume) {
  const auto torus = make_phantom("torus", {64, 64, 32}, 0);
  const double major = 0.3 * 64, minor = 0.12 * 64;
  const double expected = 2 * kPi * kPi * major * minor * minor;
  const double count = static_cast<double>(count_at_least(sample_volume(*torus), 0.5f));
  EXPECT_NEAR(count / expected, 1.0, 0.03) << count << " voxels, torus volume " << expected;
}

TEST(TopologyOracleTest, EulerCharacteristicOfKnownShapes) {
  // The helper the blob test relies on: ball 1, hollow shell 2 (component + cavity), torus 0.
  const Grid g{40, 40, 40};
  EXPECT_EQ(euler_characteristic(g, sample_volume(Sphere(g, {20, 20, 20}, 12)), 0.5f), 1);
  EXPECT_EQ(euler_characteristic(g, sample_volume(NestedShells(g, {20, 20, 20}, {15, 9})), 0.5f),
            2);
  EXPECT_EQ(euler_characteristic(g, sample_volume(Torus(g, {20, 20, 20}, 11, 4)), 0.5f), 0);
}

TEST(TorusTest, AxisIsAlongZ) {
  // Axis along z: the pattern is unchanged by swapping x and y, but not by swapping x and z.
  const Torus torus({33, 33, 33}, {16, 16, 16}, 10, 3);
  bool xz_differs = false;
  for (std::uint32_t z = 0; z < 33; ++z)
    for (std::uint32_t y = 0; y < 33; ++y)
      for (std::uint32_t x = 0; x < 33; ++x) {
        ASSERT_EQ(torus.density(x, y, z), torus.density(y, x, z));
        xz_differs |= torus.density(x, y, z) != torus.density(z, y, x);
      }
  EXPECT_TRUE(xz_differs);
  EXPECT_EQ(torus.density(26, 16, 16), 1.0f);
  EXPECT_EQ(torus.density(16, 16, 26), 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Nested shells

TEST(ShellsTest, HollowShellHasEmptyCentre) {
  // One shell: radii 25.6 and 16 around (31.5, 31.5, 31.5).
  const auto shells = make_phantom("shells", {64, 64, 64}, 0);
  EXPECT_EQ(shells->density(31, 31, 31), 0.0f);
  EXPECT_EQ(shells->density(32, 32, 32), 0.0f);
  EXPECT_EQ(shells->density(52, 31, 31), 1.0f);  // distance ~20.5, in the wall
  EXPECT_EQ(shells->density(31, 11, 31), 1.0f);
  EXPECT_EQ(shells->density(31, 31, 58), 0.0f);  // distance ~26.5, outside
  EXPECT_EQ(shells->density(0, 0, 0), 0.0f);
  const double r0 = 0.4 * 64, r1 = 0.25 * 64;
  const double expected = 4.0 / 3.0 * kPi * (r0 * r0 * r0 - r1 * r1 * r1);
  const double count = static_cast<double>(count_at_least(sample_volume(*shells), 0.5f));
  EXPECT_NEAR(count / expected, 1.0, 0.03) << count << " voxels, shell volume " << expected;
}

TEST(ShellsTest, RadiiAlternateSolidAndEmptyInward) {
  const NestedShells shells({31, 31, 31}, {15, 15, 15}, {10, 7, 4});
  const float expected_by_distance[] = {1, 1, 1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0};
  for (std::uint32_t d = 0; d <= 12; ++d) {
    EXPECT_EQ(shells.density(15 + d, 15, 15), expected_by_distance[d]) << "distance " << d;
  }
}

TEST(ShellsTest, RejectsBadRadii) {
  const Grid g{8, 8, 8};
  const Point3 c{4, 4, 4};
  EXPECT_THROW(NestedShells(g, c, {}), std::invalid_argument);
  EXPECT_THROW(NestedShells(g, c, {5, 5}), std::invalid_argument);
  EXPECT_THROW(NestedShells(g, c, {4, 6}), std::invalid_argument);
  EXPECT_THROW(NestedShells(g, c, {5, -1}), std::invalid_argument);
}

}  // namespace
}  // namespace mvox::sim
