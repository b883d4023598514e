// The renderer's contract beyond coverage (mvox/zbuffer_renderer.h): the nearer surface wins
// whatever the order, back faces culled, the lighting formula, the workspace bound, and the
// polygon sizes it takes. Coverage and shared edges are zbuffer_coverage_test.cpp's.
#include "mvox/zbuffer_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/geometric.hpp>
#include <vector>

#include "mvox/camera.h"
#include "render_canvas.h"

namespace mvox {
namespace {

using test::Canvas;
using test::cross;
using test::kPi;
using test::no_culling;
using test::pixel_camera;
using test::Sub;
using test::world_polygon;

// --- Depth ------------------------------------------------------------------------------------

TEST(ZBufferDepth, TheNearerPolygonWinsWhateverTheOrder) {
  const std::uint32_t w = 32, h = 32;
  // Square A at depth 0.25 facing the viewer; square B behind it at depth 0.65, its normal 60
  // degrees off the view axis, so the two shades differ.
  const std::vector<glm::vec3> a = {
      {4.3f, 5.1f, -0.5f}, {20.7f, 5.1f, -0.5f}, {20.7f, 19.9f, -0.5f}, {4.3f, 19.9f, -0.5f}};
  const std::vector<glm::vec3> b = {
      {12.2f, 10.6f, 0.3f}, {28.4f, 10.6f, 0.3f}, {28.4f, 27.8f, 0.3f}, {12.2f, 27.8f, 0.3f}};
  const float s = std::sqrt(3.0f) / 2;
  const std::vector<glm::vec3> normals_a(4, glm::vec3(0, 0, -1));
  const std::vector<glm::vec3> normals_b(4, glm::vec3(s, 0, -0.5f));
  Canvas a_then_b(pixel_camera(w, h), no_culling()), b_then_a(pixel_camera(w, h), no_culling()),
      a_alone(pixel_camera(w, h), no_culling()), b_alone(pixel_camera(w, h), no_culling());
  a_then_b.draw(a, &normals_a);
  a_then_b.draw(b, &normals_b);
  b_then_a.draw(b, &normals_b);
  b_then_a.draw(a, &normals_a);
  a_alone.draw(a, &normals_a);
  b_alone.draw(b, &normals_b);
  const std::size_t n = std::size_t{w} * h;
  EXPECT_EQ(0, std::memcmp(a_then_b.renderer.pixels(), b_then_a.renderer.pixels(), n));
  EXPECT_EQ(0, std::memcmp(a_then_b.renderer.depths(), b_then_a.renderer.depths(), n * 4));
  std::size_t overlap = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!a_alone.written(i)) continue;
    EXPECT_EQ(a_then_b.renderer.pixels()[i], a_alone.renderer.pixels()[i]);
    EXPECT_FLOAT_EQ(a_then_b.renderer.depths()[i], 0.25f);
    if (b_alone.written(i)) {
      ++overlap;
      EXPECT_NE(b_alone.renderer.pixels()[i], a_alone.renderer.pixels()[i]);
    }
  }
  EXPECT_GT(overlap, 50u);
  // A drawn after B overwrote the overlap: each of those fragments was written twice.
  EXPECT_EQ(b_then_a.renderer.counters().fragments_written,
            a_alone.written_count() + b_alone.written_count());
  EXPECT_EQ(a_then_b.renderer.counters().fragments_written,
            a_alone.written_count() + b_alone.written_count() - overlap);
}

TEST(ZBufferDepth, CrossingPlanesGiveTheSameImageInEitherOrderAndInterpolateDepth) {
  const std::uint32_t w = 32, h = 32;
  // Two tilted quads that pass through each other: which one is nearer changes across the image.
  // Depth is z mapped from -1..1 to 0..1 and is affine in x, so every pixel's depth is known.
  // Vertices are exact in 1/256 pixel, so the renderer's snapping moves nothing.
  const std::vector<glm::vec3> p = {{1.125f, 2.25f, -0.8f},
                                    {30.875f, 2.25f, 0.7f},
                                    {30.875f, 29.375f, 0.7f},
                                    {1.125f, 29.375f, -0.8f}};
  const std::vector<glm::vec3> q = {
      {1.25f, 1.75f, 0.6f}, {30.25f, 1.75f, -0.6f}, {30.25f, 30.5f, -0.6f}, {1.25f, 30.5f, 0.6f}};
  const std::vector<glm::vec3> up(4, glm::vec3(0, 0, -1)), tilted(4, glm::vec3(1, 0, -1));
  Canvas pq(pixel_camera(w, h), no_culling()), qp(pixel_camera(w, h), no_culling());
  pq.draw(p, &up);
  pq.draw(q, &tilted);
  qp.draw(q, &tilted);
  qp.draw(p, &up);
  const std::size_t n = std::size_t{w} * h;
  EXPECT_EQ(0, std::memcmp(pq.renderer.pixels(), qp.renderer.pixels(), n));
  EXPECT_EQ(0, std::memcmp(pq.renderer.depths(), qp.renderer.depths(), n * 4));
  int p_visible = 0, q_visible = 0;
  for (std::uint32_t y = 3; y < 29; ++y)
    for (std::uint32_t x = 2; x < 30; ++x) {
      const double cx = x + 0.5;
      const double depth_p = 0.5 * (1 + (-0.8 + 1.5 * (cx - 1.125) / 29.75));
      const double depth_q = 0.5 * (1 + (0.6 - 1.2 * (cx - 1.25) / 29.0));
      const float depth = pq.renderer.depths()[y * w + x];
      EXPECT_NEAR(depth, std::min(depth_p, depth_q), 1e-5) << x << "," << y;
      (depth_p < depth_q ? p_visible : q_visible)++;
    }
  EXPECT_GT(p_visible, 100);
  EXPECT_GT(q_visible, 100);
}

// --- Culling ----------------------------------------------------------------------------------

// The default view looks from -y with +x right and +z up (camera.h). A triangle in the plane
// y = 0 whose right-hand normal is -y faces the viewer, and it is wound counter-clockwise as
// seen: right along +x, then up along +z. mvox's meshes are wound this way seen from outside.
TEST(ZBufferCulling, TrianglesWoundClockwiseAsSeenAreCulledOnlyWhenAsked) {
  const Camera camera = fit_camera({-1, -1, -1}, {1, 1, 1}, {}, 64, 64);
  const std::vector<glm::vec3> facing = {{-0.6f, 0, -0.5f}, {0.7f, 0, -0.4f}, {-0.5f, 0, 0.8f}};
  const std::vector<glm::vec3> away = {facing[0], facing[2], facing[1]};
  ASSERT_LT(glm::cross(facing[1] - facing[0], facing[2] - facing[0]).y, 0.0f);
  for (bool cull : {true, false}) {
    Lighting lighting;
    lighting.cull_back_faces = cull;
    Canvas front(camera, lighting), back(camera, lighting);
    front.draw(facing);
    back.draw(away);
    EXPECT_EQ(front.renderer.counters().triangles_drawn, 1u) << "cull " << cull;
    EXPECT_EQ(front.renderer.counters().triangles_culled, 0u) << "cull " << cull;
    EXPECT_GT(front.written_count(), 100u) << "cull " << cull;
    EXPECT_EQ(back.renderer.counters().triangles_drawn, cull ? 0u : 1u);
    EXPECT_EQ(back.renderer.counters().triangles_culled, cull ? 1u : 0u);
    EXPECT_EQ(back.written_count(), cull ? 0u : front.written_count());
  }
}

TEST(ZBufferCulling, InScreenSpaceTheVisiblyClockwiseTriangleIsTheBackFace) {
  // Screen space (pixel_camera): counter-clockwise on the screen is cross < 0 with y down.
  const Sub a{512, 512}, b{1024, 3584}, c{3584, 1536};
  ASSERT_LT(cross(a, b, c), 0);
  Canvas front(pixel_camera(16, 16)), back(pixel_camera(16, 16));
  front.draw(world_polygon({a, b, c}));
  back.draw(world_polygon({a, c, b}));
  EXPECT_GT(front.written_count(), 10u);
  EXPECT_EQ(back.written_count(), 0u);
  EXPECT_EQ(back.renderer.counters().triangles_culled, 1u);
}

TEST(ZBufferCulling, ZeroAreaTrianglesAreCulledAndDrawNothing) {
  Canvas canvas(pixel_camera(16, 16), no_culling());
  canvas.draw({{2.5f, 2.5f, 0}, {8.5f, 8.5f, 0}, {12.5f, 12.5f, 0}});  // collinear, on centres
  canvas.draw({{4.5f, 4.5f, 0}, {4.5f, 4.5f, 0}, {9.5f, 4.5f, 0}});    // two vertices equal
  EXPECT_EQ(canvas.written_count(), 0u);
  EXPECT_EQ(canvas.renderer.counters().triangles_culled, 2u);
}

// --- Lighting ---------------------------------------------------------------------------------

int expected_shade(const Lighting& l, double cosine) {
  const double shade = l.ambient + l.diffuse * cosine + l.specular * std::pow(cosine, l.shininess);
  return static_cast<int>(std::lround(255 * std::min(1.0, shade)));
}

// The shade a flat square with per-vertex normal `normal` gets in the middle pixel.
// The square faces the viewer (counter-clockwise as seen), so culling keeps it.
int shade_of(const Lighting& lighting, const glm::vec3& normal) {
  Canvas canvas(pixel_camera(16, 16), lighting);
  const std::vector<glm::vec3> normals(4, normal);
  canvas.draw({{2.2f, 2.2f, 0}, {2.2f, 13.7f, 0}, {13.7f, 13.7f, 0}, {13.7f, 2.2f, 0}}, &normals);
  return canvas.renderer.pixels()[8 * 16 + 8];
}

TEST(ZBufferLighting, ANormalTowardsTheViewerGetsAmbientPlusDiffusePlusSpecular) {
  const Lighting defaults;
  EXPECT_EQ(expected_shade(defaults, 1.0), 255);   // 0.10 + 0.75 + 0.25 clamps to 1
  EXPECT_EQ(shade_of(defaults, {0, 0, -1}), 255);  // screen space: -z is towards the viewer
  Lighting dim;
  dim.ambient = 0.1f;
  dim.diffuse = 0.55f;
  dim.specular = 0.2f;
  dim.shininess = 8;
  EXPECT_EQ(expected_shade(dim, 1.0), 217);  // 0.85 * 255 = 216.75, not clamped
  EXPECT_EQ(shade_of(dim, {0, 0, -1}), 217);
  EXPECT_EQ(shade_of(dim, {0, 0, 3}), 217);  // two-sided, and any length
  // The headlight follows a real camera too: default view, a square facing -y.
  Canvas canvas(fit_camera({-1, -1, -1}, {1, 1, 1}, {}, 32, 32), dim);
  const std::vector<glm::vec3> normals(4, glm::vec3(0, -1, 0));
  canvas.draw({{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}}, &normals);
  EXPECT_EQ(canvas.renderer.pixels()[16 * 32 + 16], 217);
}

TEST(ZBufferLighting, ANormalAtSixtyDegreesFollowsTheFormula) {
  Lighting dim;
  dim.ambient = 0.1f;
  dim.diffuse = 0.55f;
  dim.specular = 0.2f;
  dim.shininess = 8;
  const float s = std::sqrt(3.0f) / 2;
  for (const Lighting& lighting : {Lighting(), dim})
    for (const glm::vec3 normal :
         {glm::vec3(s, 0, -0.5f), glm::vec3(0, -s, -0.5f), glm::vec3(-s * 0.6f, s * 0.8f, 0.5f)}) {
      // The renderer looks the shade up in a table of the cosine in steps of 1/1023.
      EXPECT_NEAR(shade_of(lighting, normal), expected_shade(lighting, 0.5), 1)
          << normal.x << "," << normal.y << "," << normal.z;
    }
  // A normal in the image plane: ambient only.
  EXPECT_NEAR(shade_of(dim, {1, 0, 0}), expected_shade(dim, 0.0), 1);
}

TEST(ZBufferLighting, WithoutNormalsEachTriangleIsShadedByItsOwnPlane) {
  Lighting dim = no_culling();
  dim.diffuse = 0.5f;
  Canvas canvas(pixel_camera(16, 16), dim);
  // The plane z = k (x - 8) has normal (-k, 0, 1) up to sign: cosine 1 / sqrt(1 + k^2), shade
  // about 20 grey levels below a plane facing the viewer.
  const float k = 0.15f;
  canvas.draw({{2.2f, 2.2f, k * (2.2f - 8)},
               {13.7f, 2.2f, k * (13.7f - 8)},
               {13.7f, 13.7f, k * (13.7f - 8)},
               {2.2f, 13.7f, k * (2.2f - 8)}});
  EXPECT_NEAR(canvas.renderer.pixels()[8 * 16 + 8], expected_shade(dim, 1 / std::sqrt(1 + k * k)),
              1);
  EXPECT_EQ(canvas.renderer.pixels()[0], dim.background);
}

// --- Memory -----------------------------------------------------------------------------------

TEST(ZBufferWorkspace, FiveBytesPerPixelAndAFixedFragmentBuffer) {
  const std::uint32_t sizes[][2] = {{1, 1}, {3, 2}, {17, 9}, {64, 32}, {640, 480}, {16384, 2}};
  for (const auto& size : sizes) {
    EXPECT_EQ(zbuffer_workspace_bytes(size[0], size[1]),
              5u * size[0] * size[1] + ZBufferRenderer::fragment_bytes());
    EXPECT_EQ(zbuffer_workspace_bytes(size[0], size[1]), zbuffer_workspace_bytes(size[0], size[1]));
  }
  EXPECT_EQ(zbuffer_workspace_bytes(0, 5), 0u);
  EXPECT_EQ(zbuffer_workspace_bytes(5, 0), 0u);
  EXPECT_EQ(zbuffer_workspace_bytes(kMaxImageSide + 1, 1), 0u);
  EXPECT_EQ(zbuffer_workspace_bytes(1, kMaxImageSide + 1), 0u);
}

TEST(ZBufferWorkspace, EverySizeBelowTheBoundIsRefused) {
  const std::uint32_t sizes[][2] = {{1, 1}, {3, 2}, {17, 9}, {64, 32}};
  for (const auto& size : sizes) {
    const std::size_t bound = zbuffer_workspace_bytes(size[0], size[1]);
    std::vector<float> memory(bound / sizeof(float) + 1);
    ZBufferRenderer renderer;
    const Camera camera = pixel_camera(size[0], size[1]);
    for (std::size_t bytes = 0; bytes < bound; ++bytes)
      ASSERT_EQ(renderer.init(memory.data(), bytes, camera), Status::workspace_too_small)
          << size[0] << "x" << size[1] << " with " << bytes << " of " << bound;
    EXPECT_EQ(renderer.init(memory.data(), bound, camera), Status::ok);
  }
  ZBufferRenderer renderer;
  std::vector<float> memory(64);
  EXPECT_EQ(renderer.init(nullptr, 256, pixel_camera(4, 4)), Status::invalid_argument);
  EXPECT_EQ(renderer.init(memory.data(), 256, pixel_camera(0, 4)), Status::invalid_argument);
  EXPECT_EQ(renderer.init(reinterpret_cast<char*>(memory.data()) + 1, 200, pixel_camera(4, 4)),
            Status::workspace_misaligned);
  Lighting negative;
  negative.diffuse = -1;
  EXPECT_EQ(renderer.init(memory.data(), 256, pixel_camera(4, 4), negative),
            Status::invalid_argument);
  // A refused renderer draws nothing (and does not crash).
  const glm::vec3 tri[3] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
  renderer.draw_polygon(tri, nullptr, 3);
  EXPECT_EQ(renderer.counters().polygons, 0u);
}

TEST(ZBufferWorkspace, DrawingStaysInsideTheBound) {
  const std::uint32_t w = 37, h = 23;  // odd sizes: no padding hides an overrun
  const std::size_t bound = zbuffer_workspace_bytes(w, h);
  std::vector<float> memory(bound / sizeof(float) + 64);
  auto* bytes = reinterpret_cast<unsigned char*>(memory.data());
  std::memset(bytes + bound, 0xA5, memory.size() * sizeof(float) - bound);
  ZBufferRenderer renderer;
  ASSERT_EQ(renderer.init(memory.data(), bound, pixel_camera(w, h), no_culling()), Status::ok);
  // Larger than the image on every side, in both windings.
  const glm::vec3 big[4] = {{-10, -10, 0}, {50, -10, 0}, {50, 40, 0}, {-10, 40, 0}};
  renderer.draw_polygon(big, nullptr, 4);
  const glm::vec3 reversed[4] = {big[3], big[2], big[1], big[0]};
  renderer.draw_polygon(reversed, nullptr, 4);
  EXPECT_EQ(renderer.counters().fragments_written, std::uint64_t{w} * h);
  for (std::size_t i = bound; i < memory.size() * sizeof(float); ++i)
    ASSERT_EQ(bytes[i], 0xA5) << "byte " << i << " past the workspace was written";
  for (std::size_t i = 0; i < std::size_t{w} * h; ++i) ASSERT_FLOAT_EQ(renderer.depths()[i], 0.5f);
}

TEST(ZBufferWorkspace, ClearResetsPixelsDepthsAndCounters) {
  Lighting lighting = no_culling();
  lighting.background = 7;
  Canvas canvas(pixel_camera(16, 16), lighting);
  canvas.draw({{1, 1, 0}, {15, 1, 0}, {15, 15, 0}});
  ASSERT_GT(canvas.written_count(), 0u);
  canvas.renderer.clear();
  EXPECT_EQ(canvas.written_count(), 0u);
  for (std::size_t i = 0; i < canvas.pixel_count(); ++i) EXPECT_EQ(canvas.renderer.pixels()[i], 7);
  EXPECT_EQ(canvas.renderer.counters().polygons, 0u);
  EXPECT_EQ(canvas.renderer.counters().fragments_covered, 0u);
}

TEST(ZBufferPolygons, VertexCountsOutsideThreeToSixteenAreIgnored) {
  Canvas canvas(pixel_camera(32, 32), no_culling());
  std::vector<glm::vec3> circle;
  for (int i = 0; i < 17; ++i)
    circle.push_back(
        {16 + 10 * std::cos(2 * kPi * i / 17), 16 + 10 * std::sin(2 * kPi * i / 17), 0});
  canvas.renderer.draw_polygon(circle.data(), nullptr, 17);
  canvas.renderer.draw_polygon(circle.data(), nullptr, 2);
  EXPECT_EQ(canvas.renderer.counters().polygons, 0u);
  EXPECT_EQ(canvas.written_count(), 0u);
  canvas.renderer.draw_polygon(circle.data(), nullptr, 16);
  EXPECT_EQ(canvas.renderer.counters().triangles_drawn, 14u);
}

}  // namespace
}  // namespace mvox
