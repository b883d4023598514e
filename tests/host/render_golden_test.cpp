// Golden pictures: every phantom rendered as `mvox demo --image` renders, compared with the
// picture stored in tests/golden/ within a tolerance (as VTK's regression images are), so that
// a change to the engine, the normals, the camera or the shading that alters the picture is
// seen. After a deliberate change, regenerate and look at them (tests/golden/README.md):
//   MVOX_UPDATE_GOLDEN=1 build/tests/render_golden_test
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "phantom_factory.h"
#include "phantom_picture.h"

namespace mvox {
namespace {

// Grey levels: allowed for rounding differences between compilers and machines, small enough
// that a changed normal, light or fit shows.
constexpr double kMostMeanDifference = 1.5;
constexpr double kMostChangedFraction = 0.01;  // of pixels differing by more than:
constexpr int kChangedBy = 24;

std::string golden_path(const std::string& phantom) {
  return std::string(MVOX_GOLDEN_DIR) + "/" + phantom + ".png";
}

bool updating() {
  const char* value = std::getenv("MVOX_UPDATE_GOLDEN");
  return value && std::string(value) == "1";
}

class GoldenPicture : public testing::TestWithParam<std::string> {};

TEST_P(GoldenPicture, MatchesTheStoredPicture) {
  const std::string phantom = GetParam();
  test::PhantomPictureSetup setup;
  setup.view.azimuth_deg = 30;
  setup.view.elevation_deg = 20;
  // Odd, unequal sides: an axis swap changes the picture.
  const test::PhantomPicture picture = test::render_phantom(phantom, {64, 56, 48}, setup);
  const cv::Mat rendered(static_cast<int>(picture.height), static_cast<int>(picture.width), CV_8UC1,
                         const_cast<std::uint8_t*>(picture.pixels.data()));
  // A blank picture would match a blank golden: the phantom must fill part of the frame.
  EXPECT_GT(cv::countNonZero(rendered), static_cast<int>(rendered.total() / 20));

  const std::string path = golden_path(phantom);
  if (updating()) {
    ASSERT_TRUE(cv::imwrite(path, rendered)) << path;
    std::printf("updated %s\n", path.c_str());
    return;
  }
  const cv::Mat golden = cv::imread(path, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(golden.empty()) << path << " is missing; create it with MVOX_UPDATE_GOLDEN=1 "
                               << "build/tests/render_golden_test (tests/golden/README.md)";
  ASSERT_EQ(golden.size(), rendered.size());
  cv::Mat difference;
  cv::absdiff(golden, rendered, difference);
  const double mean_difference = cv::mean(difference)[0];
  const double changed_fraction =
      static_cast<double>(cv::countNonZero(difference > kChangedBy)) / difference.total();
  EXPECT_LE(mean_difference, kMostMeanDifference) << phantom;
  EXPECT_LE(changed_fraction, kMostChangedFraction) << phantom;
}

INSTANTIATE_TEST_SUITE_P(EveryPhantom, GoldenPicture, testing::ValuesIn(sim::phantom_names()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace mvox
