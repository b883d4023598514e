// Tests for sim/: every phantom against an analytic oracle, and the simulated scanner against
// the sample mapping it promises.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "phantom.h"
#include "phantom_factory.h"
#include "random_phantoms.h"
#include "shapes.h"
#include "shepp_logan.h"
#include "simulated_scanner.h"
#include "splitmix64.h"

namespace mvox::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// density = x + 10 y + 100 z: every voxel different, so any axis swap or flip shows.
class AxisPhantom final : public Phantom {
 public:
  explicit AxisPhantom(Grid grid) : grid_(grid) {}
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override {
    return static_cast<float>(x + 10.0 * y + 100.0 * z);
  }
  const char* name() const override { return "axis"; }

 private:
  Grid grid_;
};

// One row of given densities (width = values.size(), height = depth = 1).
class RowPhantom final : public Phantom {
 public:
  explicit RowPhantom(std::vector<float> values) : values_(std::move(values)) {}
  Grid grid() const override { return {static_cast<std::uint32_t>(values_.size()), 1, 1}; }
  float density(std::uint32_t x, std::uint32_t, std::uint32_t) const override { return values_[x]; }
  const char* name() const override { return "row"; }

 private:
  std::vector<float> values_;
};

std::size_t index_of(const Grid& g, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return x + std::size_t{g.width} * (y + std::size_t{g.height} * z);
}

std::size_t count_at_least(const std::vector<float>& volume, float threshold) {
  std::size_t count = 0;
  for (float d : volume) count += d >= threshold;
  return count;
}

// Number of 6-connected components of voxels with density >= threshold.
int count_components(const Grid& g, const std::vector<float>& volume, float threshold) {
  std::vector<char> seen(volume.size(), 0);
  int components = 0;
  for (std::size_t start = 0; start < volume.size(); ++start) {
    if (seen[start] || volume[start] < threshold) continue;
    ++components;
    std::queue<std::size_t> queue;
    queue.push(start);
    seen[start] = 1;
    while (!queue.empty()) {
      const std::size_t i = queue.front();
      queue.pop();
      const std::uint32_t x = i % g.width;
      const std::uint32_t y = (i / g.width) % g.height;
      const std::uint32_t z = static_cast<std::uint32_t>(i / (std::size_t{g.width} * g.height));
      auto visit = [&](bool inside, std::size_t j) {
        if (inside && !seen[j] && volume[j] >= threshold) {
          seen[j] = 1;
          queue.push(j);
        }
      };
      visit(x > 0, i - 1);
      visit(x + 1 < g.width, i + 1);
      visit(y > 0, i - g.width);
      visit(y + 1 < g.height, i + g.width);
      visit(z > 0, i - std::size_t{g.width} * g.height);
      visit(z + 1 < g.depth, i + std::size_t{g.width} * g.height);
    }
  }
  return components;
}

// Euler characteristic of the voxels with density >= threshold, 6-connected: the cubical
// complex with a vertex per voxel, an edge per 6-adjacent pair, a square per 2x2 block and a
// cube per 2x2x2 block, which has the same topology as the 6-connected voxel set.
long euler_characteristic(const Grid& g, const std::vector<float>& volume, float threshold) {
  auto in = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) -> long {
    if (x >= g.width || y >= g.height || z >= g.depth) return 0;
    return volume[index_of(g, x, y, z)] >= threshold;
  };
  long chi = 0;
  for (std::uint32_t z = 0; z < g.depth; ++z)
    for (std::uint32_t y = 0; y < g.height; ++y)
      for (std::uint32_t x = 0; x < g.width; ++x) {
        if (!in(x, y, z)) continue;
        const long ex = in(x + 1, y, z), ey = in(x, y + 1, z), ez = in(x, y, z + 1);
        const long sxy = ex && ey && in(x + 1, y + 1, z);
        const long sxz = ex && ez && in(x + 1, y, z + 1);
        const long syz = ey && ez && in(x, y + 1, z + 1);
        const long cube = sxy && sxz && syz && in(x + 1, y + 1, z + 1);
        chi += 1 - (ex + ey + ez) + (sxy + sxz + syz) - cube;
      }
  return chi;
}

// Reads sample (x, y) of a slice view as a double, whatever its type.
double sample_at(const SliceView& view, std::uint32_t x, std::uint32_t y) {
  const char* p = static_cast<const char*>(view.samples) + y * view.row_stride_bytes +
                  x * sample_bytes(view.type);
  switch (view.type) {
    case SampleType::u8: {
      std::uint8_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::u16: {
      std::uint16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::i16: {
      std::int16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::f32: {
      float v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
  }
  return 0;
}

// Every sample of a scan, x fastest, through the scanner's own views (stride included).
std::vector<double> scan_all(SimulatedScanner& scanner) {
  std::vector<double> samples;
  SliceView view;
  while (scanner.next_slice(&view)) {
    for (std::uint32_t y = 0; y < view.height; ++y) {
      for (std::uint32_t x = 0; x < view.width; ++x) samples.push_back(sample_at(view, x, y));
    }
  }
  return samples;
}

const SampleType kAllTypes[] = {SampleType::u8, SampleType::u16, SampleType::i16, SampleType::f32};

// ---------------------------------------------------------------------------------------------
// Phantom basics

TEST(PhantomTest, SampleVolumeIsXFastestThenYThenZ) {
  const Grid g{7, 5, 6};
  const std::vector<float> volume = sample_volume(AxisPhantom(g));
  ASSERT_EQ(volume.size(), 7u * 5 * 6);
  for (std::uint32_t z = 0; z < g.depth; ++z)
    for (std::uint32_t y = 0; y < g.height; ++y)
      for (std::uint32_t x = 0; x < g.width; ++x)
        ASSERT_EQ(volume[x + 7 * (y + 5 * z)], x + 10.0f * y + 100.0f * z);
}

TEST(PhantomTest, GridCentreAndMinDimension) {
  const Point3 c = grid_centre({7, 5, 6});
  EXPECT_EQ(c.x, 3.0);
  EXPECT_EQ(c.y, 2.0);
  EXPECT_EQ(c.z, 2.5);
  EXPECT_EQ(min_dimension({7, 5, 6}), 5u);
  EXPECT_THROW(check_grid({7, 0, 6}, "test"), std::invalid_argument);
}

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

// ---------------------------------------------------------------------------------------------
// Shepp-Logan

// Table coordinates of a voxel centre, as documented in shepp_logan.h (y flipped).
Point3 table_point(const Grid& g, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return {(2.0 * x + 1) / g.width - 1, 1 - (2.0 * y + 1) / g.height, (2.0 * z + 1) / g.depth - 1};
}

TEST(SheppLoganTest, TableIsTheModifiedSheppLogan) {
  const SheppLoganEllipsoid* e = shepp_logan_ellipsoids();
  const double intensities[] = {1, -0.8, -0.2, -0.2, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1};
  for (int i = 0; i < kSheppLoganEllipsoidCount; ++i) EXPECT_EQ(e[i].intensity, intensities[i]);
  EXPECT_EQ(e[0].semi_axis_x, 0.69);
  EXPECT_EQ(e[0].semi_axis_y, 0.92);
  EXPECT_EQ(e[0].semi_axis_z, 0.81);
  EXPECT_EQ(e[1].centre_y, -0.0184);
  EXPECT_EQ(e[2].rotation_z_degrees, -18);
  EXPECT_EQ(e[3].rotation_z_degrees, 18);
}

TEST(SheppLoganTest, CentreIsSkullPlusBrain) {
  // Odd sizes put a voxel centre exactly at the table's origin, covered only by the first two
  // ellipsoids.
  const SheppLogan3D phantom({65, 65, 65});
  const SheppLoganEllipsoid* e = shepp_logan_ellipsoids();
  EXPECT_NEAR(phantom.density(32, 32, 32), e[0].intensity + e[1].intensity, 1e-6);
  EXPECT_NEAR(phantom.density(32, 32, 32), 0.2, 1e-6);
}

TEST(SheppLoganTest, SkullIsOneWhereOnlyOuterEllipsoidCovers) {
  // Ellipsoids 1 and 2 written out independently of the implementation's table.
  const Grid g{64, 64, 64};
  const SheppLogan3D phantom(g);
  int skull_voxels = 0;
  for (std::uint32_t z = 0; z < g.depth; ++z)
    for (std::uint32_t y = 0; y < g.height; ++y)
      for (std::uint32_t x = 0; x < g.width; ++x) {
        const Point3 p = table_point(g, x, y, z);
        const bool in_outer =
            std::pow(p.x / 0.69, 2) + std::pow(p.y / 0.92, 2) + std::pow(p.z / 0.81, 2) <= 1;
        const bool in_inner = std::pow(p.x / 0.6624, 2) + std::pow((p.y + 0.0184) / 0.874, 2) +
                                  std::pow(p.z / 0.78, 2) <=
                              1;
        if (in_outer && !in_inner) {
          ++skull_voxels;
          ASSERT_EQ(phantom.density(x, y, z), 1.0f) << x << "," << y << "," << z;
        } else if (!in_outer) {
          ASSERT_EQ(phantom.density(x, y, z), 0.0f) << x << "," << y << "," << z;
        }
      }
  // The shell is about 0.262 of the 8 cubic units of the grid: about 8,600 voxels of 64^3.
  EXPECT_GT(skull_voxels, 6000);
}

TEST(SheppLoganTest, AxialSlicesHaveTheFamiliarOrientation) {
  const Grid g{65, 65, 65};
  const SheppLogan3D phantom(g);
  // The large ellipse (table y = +0.35, z = -0.15) sits in the upper rows of the image...
  const Point3 upper = table_point(g, 32, 21, 27);
  EXPECT_NEAR(upper.y, 0.338, 1e-3);
  EXPECT_NEAR(phantom.density(32, 21, 27), 0.3, 1e-6);
  // ...and its mirror image in the lower rows is plain brain.
  EXPECT_NEAR(phantom.density(32, 65 - 1 - 21, 27), 0.2, 1e-6);
  // The ventricle at table x = +0.22 is in the right-hand columns, with density 0.
  EXPECT_NEAR(phantom.density(39, 32, 32), 0.0, 1e-6);
  EXPECT_NEAR(phantom.density(65 - 1 - 39, 32, 32), 0.0, 1e-6);  // the other one at -0.22
  // The skull is thicker at the top (rows near 0) than at the bottom.
  const Grid tall{129, 129, 129};
  const SheppLogan3D fine(tall);
  int top = 0, bottom = 0;
  for (std::uint32_t y = 0; y < 129; ++y) {
    if (fine.density(64, y, 64) == 1.0f) (y < 64 ? top : bottom)++;
  }
  EXPECT_EQ(top, 4);     // table y in (0.8556, 0.92): 0.0644 * 64.5 rows
  EXPECT_EQ(bottom, 2);  // table y in (-0.92, -0.8924): 0.0276 * 64.5 rows
}

TEST(SheppLoganTest, DefaultThresholdKeepsSkullAndBrightFeaturesOnly) {
  const double t = default_density_threshold("shepp-logan");
  const SheppLogan3D phantom({65, 65, 65});
  EXPECT_LT(phantom.density(32, 32, 32), t);  // brain 0.2
  EXPECT_LT(phantom.density(39, 32, 32), t);  // ventricle 0.0
  EXPECT_GE(phantom.density(32, 21, 27), t);  // bright ellipse 0.3
  EXPECT_GE(phantom.density(32, 3, 32), t);   // skull 1.0 (table y = 0.892)
  const std::vector<float> volume = sample_volume(phantom);
  // Skull plus separate bright features: more than one component.
  EXPECT_GE(count_components({65, 65, 65}, volume, static_cast<float>(t)), 2);
}

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

// ---------------------------------------------------------------------------------------------
// Factory

TEST(FactoryTest, EveryNameMakesItsPhantom) {
  const Grid g{16, 12, 10};
  const std::vector<std::string> expected = {"sphere",      "torus", "shells",
                                             "shepp-logan", "blobs", "random"};
  ASSERT_EQ(phantom_names(), expected);
  for (const std::string& name : phantom_names()) {
    const auto phantom = make_phantom(name, g, 1);
    ASSERT_NE(phantom, nullptr);
    EXPECT_EQ(phantom->name(), name);
    EXPECT_EQ(phantom->grid().width, 16u);
    EXPECT_EQ(phantom->grid().height, 12u);
    EXPECT_EQ(phantom->grid().depth, 10u);
    const double t = default_density_threshold(name);
    EXPECT_GT(t, 0);
    EXPECT_LT(t, 1);
    // Something is inside and something outside at the default threshold.
    const std::vector<float> volume = sample_volume(*phantom);
    const std::size_t inner = count_at_least(volume, static_cast<float>(t));
    EXPECT_GT(inner, 0u) << name;
    EXPECT_LT(inner, volume.size()) << name;
  }
  EXPECT_EQ(default_density_threshold("sphere"), 0.5);
  EXPECT_EQ(default_density_threshold("random"), 0.5);
  EXPECT_EQ(default_density_threshold("shepp-logan"), 0.25);
}

TEST(FactoryTest, UnknownNameThrowsListingValidNames) {
  try {
    make_phantom("cube", {8, 8, 8}, 0);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cube"), std::string::npos) << message;
    for (const std::string& name : phantom_names()) {
      EXPECT_NE(message.find(name), std::string::npos) << message;
    }
  }
  EXPECT_THROW(default_density_threshold("cube"), std::invalid_argument);
  EXPECT_THROW(make_phantom("sphere", {8, 8, 0}, 0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Simulated scanner

TEST(ScannerTest, YieldsDepthSlicesThenFalse) {
  const auto sphere = make_phantom("sphere", {7, 5, 6}, 0);
  for (SampleType type : kAllTypes) {
    SimulatedScanner scanner(*sphere, default_scan_options(type));
    const VolumeInfo& info = scanner.info();
    EXPECT_EQ(info.width, 7u);
    EXPECT_EQ(info.height, 5u);
    EXPECT_EQ(info.depth, 6u);
    EXPECT_EQ(info.type, type);
    SliceView view;
    std::set<const void*> buffers;
    std::uint32_t slices = 0;
    while (scanner.next_slice(&view)) {
      ++slices;
      EXPECT_EQ(view.width, 7u);
      EXPECT_EQ(view.height, 5u);
      EXPECT_EQ(view.type, type);
      EXPECT_EQ(view.row_stride_bytes, 7 * sample_bytes(type));
      buffers.insert(view.samples);
      ASSERT_LE(slices, 6u);
    }
    EXPECT_EQ(slices, 6u) << sample_type_name(type);
    EXPECT_EQ(buffers.size(), 1u) << "one slice buffer, reused";
    EXPECT_FALSE(scanner.next_slice(&view));
  }
}

TEST(ScannerTest, RewindStreamsTheSameSlicesAgain) {
  const auto blobs = make_phantom("blobs", {12, 10, 9}, 4);
  SimulatedScanner scanner(*blobs, default_scan_options(SampleType::u16));
  const std::vector<double> first = scan_all(scanner);
  EXPECT_EQ(first.size(), 12u * 10 * 9);
  scanner.rewind();
  EXPECT_EQ(scan_all(scanner), first);
  // Rewinding half-way restarts at slice 0 too.
  scanner.rewind();
  SliceView view;
  ASSERT_TRUE(scanner.next_slice(&view));
  ASSERT_TRUE(scanner.next_slice(&view));
  scanner.rewind();
  EXPECT_EQ(scan_all(scanner), first);
}

TEST(ScannerTest, InfoCarriesSpacingAndOrigin) {
  const auto sphere = make_phantom("sphere", {8, 8, 8}, 0);
  ScanOptions options;
  options.spacing[0] = 0.5;
  options.spacing[1] = 0.75;
  options.spacing[2] = 2.0;
  options.origin[2] = -10;
  SimulatedScanner scanner(*sphere, options);
  EXPECT_EQ(scanner.info().spacing[0], 0.5);
  EXPECT_EQ(scanner.info().spacing[1], 0.75);
  EXPECT_EQ(scanner.info().spacing[2], 2.0);
  EXPECT_EQ(scanner.info().origin[0], 0.0);
  EXPECT_EQ(scanner.info().origin[2], -10.0);
}

TEST(ScannerTest, RoundsAndClampsForEachType) {
  const RowPhantom row({-1e4f, -1, -0.25f, 0, 0.04f, 0.06f, 0.25f, 1, 1e4f});
  struct Case {
    SampleType type;
    double offset;
    std::vector<double> expected;
  };
  const Case cases[] = {
      {SampleType::u8, 0, {0, 0, 0, 0, 0, 1, 3, 10, 255}},
      {SampleType::u16, 0, {0, 0, 0, 0, 0, 1, 3, 10, 65535}},
      {SampleType::i16, 0, {-32768, -10, -3, 0, 0, 1, 3, 10, 32767}},  // halves away from 0
      {SampleType::f32, 0.5, {-99999.5, -9.5, -2, 0.5, 0.9, 1.1, 3, 10.5, 100000.5}},
  };
  for (const Case& c : cases) {
    ScanOptions options;
    options.type = c.type;
    options.scale = 10;
    options.offset = c.offset;
    SimulatedScanner scanner(row, options);
    const std::vector<double> samples = scan_all(scanner);
    ASSERT_EQ(samples.size(), c.expected.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      EXPECT_FLOAT_EQ(samples[i], c.expected[i]) << sample_type_name(c.type) << " sample " << i;
    }
  }
}

TEST(ScannerTest, DefaultOptionsMapZeroAndOne) {
  const RowPhantom row({0, 1});
  const double expected[][2] = {{0, 255}, {0, 4095}, {-1024, 2047}, {0, 1}};
  int i = 0;
  for (SampleType type : kAllTypes) {
    SimulatedScanner scanner(row, default_scan_options(type));
    const std::vector<double> samples = scan_all(scanner);
    EXPECT_EQ(samples[0], expected[i][0]) << sample_type_name(type);
    EXPECT_EQ(samples[1], expected[i][1]) << sample_type_name(type);
    ++i;
  }
}

TEST(ScannerTest, SampleThresholdIsExactForBinaryPhantoms) {
  const Grid g{16, 13, 11};
  const Sphere sphere(g, {9, 6, 5}, 4.5);
  const std::vector<float> densities = sample_volume(sphere);
  for (SampleType type : kAllTypes) {
    const ScanOptions options = default_scan_options(type);
    SimulatedScanner scanner(sphere, options);
    const std::vector<double> samples = scan_all(scanner);
    ASSERT_EQ(samples.size(), densities.size());
    for (double t : {0.0001, 0.001, 0.25, 0.5, 0.999, 1.0}) {
      const double s = sample_threshold(t, options);
      for (std::size_t i = 0; i < samples.size(); ++i) {
        ASSERT_EQ(densities[i] >= t, samples[i] >= s)
            << sample_type_name(type) << " t = " << t << " voxel " << i;
      }
    }
  }
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::u8)), 128);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::u16)), 2048);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::i16)), 512);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::f32)), 0.5);
  // Out of range thresholds clamp to the type.
  EXPECT_EQ(sample_threshold(2.0, default_scan_options(SampleType::u8)), 255);
  EXPECT_EQ(sample_threshold(-1.0, default_scan_options(SampleType::u8)), 0);
}

TEST(ScannerTest, SampleThresholdSeparatesSheppLoganLevels) {
  // The default Shepp-Logan threshold must keep brain (0.2) and bright features (0.3) apart
  // after quantisation to every sample type.
  const double t = default_density_threshold("shepp-logan");
  for (SampleType type : kAllTypes) {
    const ScanOptions options = default_scan_options(type);
    const double s = sample_threshold(t, options);
    EXPECT_LT(sample_value(0.2f, options), s) << sample_type_name(type);
    EXPECT_GE(sample_value(0.3f, options), s) << sample_type_name(type);
  }
}

TEST(ScannerTest, AsymmetricGridKeepsAxesStraight) {
  const Grid g{7, 5, 6};
  // A sphere off the grid centre (3, 2, 2.5) on x only.
  const Sphere sphere(g, {4, 2, 2.5}, 1.6);
  SimulatedScanner scanner(sphere, default_scan_options(SampleType::u8));
  SliceView view;
  double sum[3] = {0, 0, 0};
  int inner = 0;
  for (std::uint32_t z = 0; scanner.next_slice(&view); ++z) {
    for (std::uint32_t y = 0; y < view.height; ++y)
      for (std::uint32_t x = 0; x < view.width; ++x) {
        const bool expected =
            std::pow(x - 4.0, 2) + std::pow(y - 2.0, 2) + std::pow(z - 2.5, 2) <= 1.6 * 1.6;
        const bool is_inner = sample_at(view, x, y) >= 128;
        ASSERT_EQ(is_inner, expected) << x << "," << y << "," << z;
        if (is_inner) {
          sum[0] += x;
          sum[1] += y;
          sum[2] += z;
          ++inner;
        }
      }
  }
  ASSERT_GT(inner, 0);
  EXPECT_DOUBLE_EQ(sum[0] / inner, 4.0);  // shifted by +1 from the grid centre in x
  EXPECT_DOUBLE_EQ(sum[1] / inner, 2.0);
  EXPECT_DOUBLE_EQ(sum[2] / inner, 2.5);

  // Every voxel distinct: the f32 sample at (column x, row y, slice z) is x + 10 y + 100 z.
  const AxisPhantom axis(g);
  SimulatedScanner axis_scanner(axis, default_scan_options(SampleType::f32));
  for (std::uint32_t z = 0; axis_scanner.next_slice(&view); ++z) {
    ASSERT_LT(z, 6u);
    for (std::uint32_t y = 0; y < 5; ++y)
      for (std::uint32_t x = 0; x < 7; ++x)
        ASSERT_EQ(sample_at(view, x, y), x + 10.0 * y + 100.0 * z);
  }
}

TEST(ScannerTest, RejectsBadOptions) {
  const auto sphere = make_phantom("sphere", {8, 8, 8}, 0);
  ScanOptions options;
  options.scale = 0;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.scale = -255;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.scale = std::nan("");
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options = ScanOptions{};
  options.offset = INFINITY;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options = ScanOptions{};
  options.spacing[1] = 0;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
}

}  // namespace
}  // namespace mvox::sim
