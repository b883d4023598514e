#pragma once
// Test support for the renderer (mvox/zbuffer_renderer.h): a camera in screen space, a renderer
// with its own workspace, and points in exact 1/256 pixel units, so that tests can reason about
// pixel centres exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "mvox/camera.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox::test {

constexpr std::int64_t kSubpixel = 256;  // test coordinates are exact multiples of 1/256 pixel
constexpr double kPi = 3.14159265358979323846;

// A camera in screen space: world x, y are image pixels (x right, y down like the image rows)
// and world z in -1 .. 1, pointing into the screen, is depth 0 .. 1. That frame is right-handed
// and the camera a rotation (180 degrees about x), not a mirror, so windings keep their meaning:
// a triangle is front-facing when counter-clockwise as seen, cross(a, b, c) < 0 with y down, and
// its right-hand normal then points towards the viewer, -z. Power-of-two image sizes keep the
// projection exact in float: a vertex at (x, y) lands exactly on pixel position (x, y), so the
// oracles of the tests can reason about pixel centres exactly.
Camera pixel_camera(std::uint32_t width, std::uint32_t height);

// A renderer with its own workspace. The renderer cannot move, so neither can this.
struct Canvas {
  explicit Canvas(const Camera& camera, const Lighting& lighting = {})
      : memory(zbuffer_workspace_bytes(camera.width, camera.height) / sizeof(float) + 1) {
    EXPECT_EQ(renderer.init(memory.data(), memory.size() * sizeof(float), camera, lighting),
              Status::ok);
  }
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  std::size_t pixel_count() const { return std::size_t{renderer.width()} * renderer.height(); }
  bool written(std::size_t i) const { return std::isfinite(renderer.depths()[i]); }
  std::vector<bool> written_mask() const {
    std::vector<bool> mask(pixel_count());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = written(i);
    return mask;
  }
  std::size_t written_count() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < pixel_count(); ++i) n += written(i);
    return n;
  }
  void draw(const std::vector<glm::vec3>& positions,
            const std::vector<glm::vec3>* normals = nullptr) {
    renderer.draw_polygon(positions.data(), normals ? normals->data() : nullptr,
                          static_cast<int>(positions.size()));
  }

  std::vector<float> memory;  // float-aligned, as init() asks
  ZBufferRenderer renderer;
};

// A point in 1/256 pixel units, y down.
struct Sub {
  std::int64_t x = 0, y = 0;
};

// The point as a world position of pixel_camera(), at `z`.
glm::vec3 to_world(const Sub& p, float z = 0.0f);

// (a - o) x (b - o): negative when o, a, b turn counter-clockwise as seen (y down), zero when
// they are collinear.
std::int64_t cross(const Sub& o, const Sub& a, const Sub& b);

// The points as world positions at `z`, for Canvas::draw.
std::vector<glm::vec3> world_polygon(const std::vector<Sub>& points, float z = 0.0f);

// For geometry whose winding is not what a test is about.
Lighting no_culling();

}  // namespace mvox::test
