// The 3-D Shepp-Logan head (sim/shepp_logan.h): the modified table, the skull and brain where
// the ellipsoids say, the familiar orientation of axial slices, and a default threshold that
// keeps the skull and bright features only.
#include "shepp_logan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "phantom_factory.h"
#include "phantom_measures.h"

namespace mvox::sim {
namespace {

using test::count_components;

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

}  // namespace
}  // namespace mvox::sim
