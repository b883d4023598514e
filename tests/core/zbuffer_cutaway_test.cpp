// The cutaway (ViewOptions::cut, Camera::cut_depth): nothing nearer than the plane is drawn, and
// on a closed surface (culling on) the plane is capped where it lies inside the solid, which the
// renderer knows because the first surface behind it there faces away.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "mvox/camera.h"
#include "mvox/zbuffer_renderer.h"
#include "phantom_picture.h"

namespace mvox {
namespace {

// A cap shade the lighting cannot produce (the ambient term alone is 0.1 * 255), so that a
// pixel of this shade is a cap and nothing else.
constexpr std::uint8_t kCap = 7;

test::PhantomPicture render(const char* phantom, const sim::Grid& grid, ViewOptions view,
                            bool closed = true) {
  test::PhantomPictureSetup setup;
  setup.view = view;
  setup.lighting.cap = kCap;
  setup.lighting.cull_back_faces = closed;
  return test::render_phantom(phantom, grid, setup);
}

std::size_t count_shade(const test::PhantomPicture& picture, std::uint8_t shade) {
  std::size_t count = 0;
  for (std::uint8_t pixel : picture.pixels) count += pixel == shade;
  return count;
}

std::size_t count_drawn(const test::PhantomPicture& picture) {
  std::size_t count = 0;
  for (float depth : picture.depths) count += depth != std::numeric_limits<float>::infinity();
  return count;
}

TEST(Cutaway, NoCutMeansCutDepthZeroAndMoreCutMeansDeeper) {
  for (const bool perspective : {false, true}) {
    SCOPED_TRACE(perspective ? "perspective" : "orthographic");
    ViewOptions view;
    view.azimuth_deg = 30;
    view.elevation_deg = 20;
    view.perspective = perspective;
    EXPECT_EQ(fit_camera({0, 0, 0}, {10, 20, 30}, view, 64, 64).cut_depth, 0.0f);
    float previous = 0;
    for (const float cut : {0.1f, 0.3f, 0.5f, 0.7f, 0.9f}) {
      view.cut = cut;
      const float depth = fit_camera({0, 0, 0}, {10, 20, 30}, view, 64, 64).cut_depth;
      EXPECT_GT(depth, previous) << "cut " << cut;
      EXPECT_LT(depth, 1.0f) << "cut " << cut;
      previous = depth;
    }
  }
  // Orthographic depth is linear along the view, and the box centre is halfway.
  ViewOptions half;
  half.cut = 0.5f;
  EXPECT_NEAR(fit_camera({0, 0, 0}, {10, 20, 30}, half, 64, 64).cut_depth, 0.5f, 1e-5f);
}

TEST(Cutaway, ASolidBallCutThroughItsCentreIsOneCapOfItsOutline) {
  const sim::Grid grid{48, 48, 48};
  ViewOptions view;
  view.azimuth_deg = 25;
  view.elevation_deg = 35;
  const test::PhantomPicture whole = render("sphere", grid, view);
  view.cut = 0.5f;
  const test::PhantomPicture cut = render("sphere", grid, view);
  EXPECT_EQ(count_shade(whole, kCap), 0u);
  // Every ray that met the ball meets the far half's inside first: the outline is all cap, but
  // for pixels along the rim where the cut plane misses the ball's widest circle.
  const std::size_t outline = count_drawn(whole), caps = count_shade(cut, kCap);
  EXPECT_GT(caps, outline * 9 / 10) << caps << " cap pixels of " << outline;
  EXPECT_LE(count_drawn(cut), outline);
  // Nothing is drawn in front of the plane.
  for (std::size_t i = 0; i < cut.depths.size(); ++i)
    ASSERT_GE(cut.depths[i], cut.camera.cut_depth) << "pixel " << i;
}

TEST(Cutaway, AHollowShellShowsACapRingAndItsInnerWall) {
  // "shells": a hollow ball, radii 0.4 and 0.25 of the grid, cut through the centre and seen
  // from the front. The cap is the ring between the radii; inside it the view goes through the
  // hollow to the far half's inner wall, lit, not capped.
  const sim::Grid grid{64, 64, 64};
  ViewOptions view;
  view.cut = 0.5f;
  const test::PhantomPicture cut = render("shells", grid, view);
  const std::size_t centre = (cut.height / 2) * cut.width + cut.width / 2;
  EXPECT_NE(cut.pixels[centre], kCap);
  EXPECT_LT(cut.depths[centre], std::numeric_limits<float>::infinity());
  const double caps = static_cast<double>(count_shade(cut, kCap));
  const double drawn = static_cast<double>(count_drawn(cut));
  // The ring's share of the outline: 1 - (0.25 / 0.4)^2 = 0.61.
  EXPECT_NEAR(caps / drawn, 1.0 - (0.25 / 0.4) * (0.25 / 0.4), 0.05);
}

TEST(Cutaway, WithoutCullingTheCutRemovesTheNearPartAndCapsNothing) {
  // Culling off is for meshes not known to be closed (mvox render without --cull): the inside
  // of the far half is lit two-sided instead of capped.
  const sim::Grid grid{48, 48, 48};
  ViewOptions view;
  view.cut = 0.5f;
  const test::PhantomPicture open = render("sphere", grid, view, /*closed=*/false);
  EXPECT_EQ(count_shade(open, kCap), 0u);
  EXPECT_GT(count_drawn(open), open.pixels.size() / 10);
  for (std::size_t i = 0; i < open.depths.size(); ++i)
    ASSERT_GE(open.depths[i], open.camera.cut_depth) << "pixel " << i;
}

}  // namespace
}  // namespace mvox
