// The camera's conventions (mvox/camera.h): a fitted box inside the image touching the margin,
// the default view and the view angles, perspective, and polygons behind a perspective camera
// clipped; checked by projecting points and through the renderer.
#include "mvox/camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "render_canvas.h"

namespace mvox {
namespace {

using test::Canvas;
using test::no_culling;

// Where the renderer puts a world point: pixel position (y down) and depth 0 (near) .. 1 (far),
// by the OpenGL conventions camera.h states.
glm::vec3 project(const Camera& camera, const glm::vec3& p) {
  const glm::vec4 clip = camera.world_to_clip * glm::vec4(p, 1.0f);
  const glm::vec3 ndc = glm::vec3(clip) / clip.w;
  return {(ndc.x + 1) * 0.5f * camera.width, (1 - ndc.y) * 0.5f * camera.height,
          (ndc.z + 1) * 0.5f};
}

std::array<glm::vec3, 8> corners(const glm::vec3& lo, const glm::vec3& hi) {
  std::array<glm::vec3, 8> out;
  for (int c = 0; c < 8; ++c)
    out[c] = {(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
  return out;
}

TEST(Camera, AFittedBoxIsInsideTheImageAndTouchesTheMargin) {
  const glm::vec3 lo(-3, 2, 10), hi(40, 17, 25);  // asymmetric, off the origin
  const std::uint32_t sizes[][2] = {{256, 256}, {320, 200}, {100, 300}};
  const float views[][3] = {{0, 0, 0}, {90, 0, 0}, {37, 21, 0}, {-120, 65, 15}, {10, 90, 0}};
  for (const auto& size : sizes)
    for (const auto& angles : views)
      for (bool perspective : {false, true}) {
        ViewOptions view;
        view.azimuth_deg = angles[0];
        view.elevation_deg = angles[1];
        view.roll_deg = angles[2];
        view.perspective = perspective;
        const Camera camera = fit_camera(lo, hi, view, size[0], size[1]);
        const float w = static_cast<float>(size[0]), h = static_cast<float>(size[1]);
        glm::vec3 min_p(1e9f), max_p(-1e9f);
        for (const glm::vec3& corner : corners(lo, hi)) {
          const glm::vec3 p = project(camera, corner);
          min_p = glm::min(min_p, p);
          max_p = glm::max(max_p, p);
        }
        const std::string where = std::to_string(size[0]) + "x" + std::to_string(size[1]) + " az " +
                                  std::to_string(angles[0]) + " el " + std::to_string(angles[1]) +
                                  (perspective ? " persp" : " ortho");
        const float tolerance = 1e-3f * std::max(w, h);
        EXPECT_GE(min_p.x, view.margin * w - tolerance) << where;
        EXPECT_LE(max_p.x, (1 - view.margin) * w + tolerance) << where;
        EXPECT_GE(min_p.y, view.margin * h - tolerance) << where;
        EXPECT_LE(max_p.y, (1 - view.margin) * h + tolerance) << where;
        EXPECT_GT(min_p.z, 0.0f) << where;  // between the near and far planes
        EXPECT_LT(max_p.z, 1.0f) << where;
        if (!perspective) {
          // Exactly fitted: centred, and on one axis the box spans the image less the margins.
          EXPECT_NEAR(min_p.x + max_p.x, w, tolerance) << where;
          EXPECT_NEAR(min_p.y + max_p.y, h, tolerance) << where;
          const bool touches_x = std::fabs(max_p.x - (1 - view.margin) * w) < tolerance;
          const bool touches_y = std::fabs(max_p.y - (1 - view.margin) * h) < tolerance;
          EXPECT_TRUE(touches_x || touches_y) << where;
        }
      }
}

TEST(Camera, TheDefaultViewHasXToTheRightAndZUpAndLooksAlongY) {
  const Camera camera = fit_camera({-1, -1, -1}, {1, 1, 1}, {}, 200, 100);
  const glm::vec3 centre = project(camera, {0, 0, 0});
  EXPECT_NEAR(centre.x, 100, 1e-3);
  EXPECT_NEAR(centre.y, 50, 1e-3);
  EXPECT_GT(project(camera, {0.5f, 0, 0}).x, centre.x + 5);  // +x right
  EXPECT_NEAR(project(camera, {0.5f, 0, 0}).y, centre.y, 1e-3);
  EXPECT_LT(project(camera, {0, 0, 0.5f}).y, centre.y - 5);  // +z up (rows count down)
  EXPECT_NEAR(project(camera, {0, 0, 0.5f}).x, centre.x, 1e-3);
  EXPECT_LT(project(camera, {0, -0.5f, 0}).z, centre.z);  // seen from -y: -y is nearer
  EXPECT_NEAR(project(camera, {0, -0.5f, 0}).x, centre.x, 1e-3);
  EXPECT_NEAR(project(camera, {0, -0.5f, 0}).y, centre.y, 1e-3);
  // The same through the renderer: a small square on the +x, +z side lands right and up.
  Canvas canvas(camera);
  const std::vector<glm::vec3> square = {
      {0.5f, 0, 0.5f}, {0.7f, 0, 0.5f}, {0.7f, 0, 0.7f}, {0.5f, 0, 0.7f}};  // faces -y
  canvas.draw(square);
  ASSERT_GT(canvas.written_count(), 0u);
  for (std::size_t i = 0; i < canvas.pixel_count(); ++i)
    if (canvas.written(i)) {
      EXPECT_GT(i % 200, 100u);
      EXPECT_LT(i / 200, 50u);
    }
}

TEST(Camera, AzimuthNinetyLooksFromPlusXAndElevationNinetyFromAbove) {
  const glm::vec3 lo(-1, -1, -1), hi(1, 1, 1);
  ViewOptions side;
  side.azimuth_deg = 90;
  const Camera from_x = fit_camera(lo, hi, side, 64, 64);
  EXPECT_LT(project(from_x, {0.5f, 0, 0}).z, project(from_x, {-0.5f, 0, 0}).z);
  EXPECT_NEAR(project(from_x, {0.5f, 0, 0}).x, 32, 1e-3);  // along the view axis
  EXPECT_LT(project(from_x, {0, 0, 0.5f}).y, 32 - 5);      // z still up
  EXPECT_GT(project(from_x, {0, 0.5f, 0}).x, 32 + 5);      // turned towards +x, +y is right
  ViewOptions above;
  above.elevation_deg = 90;
  const Camera from_z = fit_camera(lo, hi, above, 64, 64);
  EXPECT_LT(project(from_z, {0, 0, 0.5f}).z, project(from_z, {0, 0, -0.5f}).z);
  EXPECT_NEAR(project(from_z, {0, 0, 0.5f}).x, 32, 1e-3);
  EXPECT_NEAR(project(from_z, {0, 0, 0.5f}).y, 32, 1e-3);
  EXPECT_GT(project(from_z, {0.5f, 0, 0}).x, 32 + 5);  // x still right
  // Roll 90 turns the picture counter-clockwise: +x, which was right, now points up.
  ViewOptions rolled;
  rolled.roll_deg = 90;
  const Camera roll = fit_camera(lo, hi, rolled, 64, 64);
  EXPECT_LT(project(roll, {0.5f, 0, 0}).y, 32 - 5);
  EXPECT_NEAR(project(roll, {0.5f, 0, 0}).x, 32, 1e-3);
}

TEST(Camera, InPerspectiveNearerThingsLookLarger) {
  ViewOptions view;
  view.perspective = true;
  const Camera camera = fit_camera({-1, -1, -1}, {1, 1, 1}, view, 128, 128);
  // Two equal squares facing the viewer (-y), one near the front of the box and one at the back.
  auto projected_width = [&](float y) {
    return project(camera, {0.2f, y, 0}).x - project(camera, {-0.2f, y, 0}).x;
  };
  EXPECT_GT(projected_width(-0.8f), projected_width(0.8f) * 1.1f);
  Canvas canvas(camera);
  auto covered = [&](float y) {
    canvas.renderer.clear();
    canvas.draw({{-0.2f, y, -0.2f}, {0.2f, y, -0.2f}, {0.2f, y, 0.2f}, {-0.2f, y, 0.2f}});
    return canvas.written_count();
  };
  EXPECT_GT(covered(-0.8f), covered(0.8f) * 1.2);
  // Orthographic: the same size at any depth.
  const Camera flat = fit_camera({-1, -1, -1}, {1, 1, 1}, {}, 128, 128);
  EXPECT_NEAR(project(flat, {0.2f, -0.8f, 0}).x - project(flat, {-0.2f, -0.8f, 0}).x,
              project(flat, {0.2f, 0.8f, 0}).x - project(flat, {-0.2f, 0.8f, 0}).x, 1e-3);
}

TEST(Camera, PolygonsBehindThePerspectiveCameraAreClippedNotDrawn) {
  ViewOptions view;
  view.perspective = true;
  const Camera camera = fit_camera({-1, -1, -1}, {1, 1, 1}, view, 64, 64);
  Canvas canvas(camera, no_culling());
  // The camera stands on the -y side; a point far out on -y is behind it.
  canvas.draw({{-0.5f, -1000, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}});
  EXPECT_EQ(canvas.renderer.counters().polygons_clipped, 1u);
  EXPECT_EQ(canvas.written_count(), 0u);
}

}  // namespace
}  // namespace mvox
