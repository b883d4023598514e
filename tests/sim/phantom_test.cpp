// The phantom interface (sim/phantom.h): sample_volume's order, x fastest then y then z, and the
// grid helpers.
#include "phantom.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "phantom_measures.h"

namespace mvox::sim {
namespace {

using test::AxisPhantom;

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

}  // namespace
}  // namespace mvox::sim
