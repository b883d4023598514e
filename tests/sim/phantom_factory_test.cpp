// The phantom factory (sim/phantom_factory.h): every name makes its phantom, with something
// inside and outside at its default threshold; unknown names are refused listing the valid ones.
#include "phantom_factory.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "phantom_measures.h"

namespace mvox::sim {
namespace {

using test::count_at_least;

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

}  // namespace
}  // namespace mvox::sim
