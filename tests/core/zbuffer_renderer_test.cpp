// The renderer's contract: exact coverage under the top-left rule, shared edges drawn once, the
// nearer surface wins whatever the order, back faces culled, the lighting formula, the workspace
// bound; and the camera's conventions (fit, view directions, perspective).
#include "mvox/zbuffer_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "mvox/camera.h"

namespace mvox {
namespace {

constexpr std::int64_t kSubpixel = 256;  // test coordinates are exact multiples of 1/256 pixel
constexpr double kPi = 3.14159265358979323846;

// A camera in screen space: world x, y are image pixels (x right, y down like the image rows)
// and world z in -1 .. 1, pointing into the screen, is depth 0 .. 1. That frame is right-handed
// and the camera a rotation (180 degrees about x), not a mirror, so windings keep their meaning:
// a triangle is front-facing when counter-clockwise as seen, cross(a, b, c) < 0 with y down, and
// its right-hand normal then points towards the viewer, -z. Power-of-two image sizes keep the
// projection exact in float: a vertex at (x, y) lands exactly on pixel position (x, y), so the
// oracles below can reason about pixel centres exactly.
Camera pixel_camera(std::uint32_t width, std::uint32_t height) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  glm::mat4 m(1.0f);  // glm is column-major: m[column][row]
  m[0][0] = 2.0f / static_cast<float>(width);
  m[3][0] = -1.0f;
  m[1][1] = -2.0f / static_cast<float>(height);
  m[3][1] = 1.0f;
  camera.world_to_clip = m;
  camera.world_to_view = glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, -1));
  return camera;
}

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

glm::vec3 to_world(const Sub& p, float z = 0.0f) {
  return {static_cast<float>(p.x) / kSubpixel, static_cast<float>(p.y) / kSubpixel, z};
}

std::int64_t cross(const Sub& o, const Sub& a, const Sub& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

Sub pixel_centre(std::int64_t px, std::int64_t py) {
  return {px * kSubpixel + kSubpixel / 2, py * kSubpixel + kSubpixel / 2};
}

// The coverage oracle, written without the renderer's edge biases: a pixel centre P belongs to
// triangle abc (either winding) when P + (e, e^2), for an infinitesimally small e > 0, lies
// strictly inside. Strictly inside points are in; a point on an edge is in when the triangle
// lies to its right (+x), or directly below it (+y) for a horizontal edge; that is the top-left
// rule, decided by symbolic perturbation instead of per-edge flags.
bool oracle_covers(const Sub tri[3], const Sub& p) {
  const std::int64_t area = cross(tri[0], tri[1], tri[2]);
  if (area == 0) return false;
  const std::int64_t sign = area > 0 ? 1 : -1;
  for (int i = 0; i < 3; ++i) {
    const Sub& a = tri[i];
    const Sub& b = tri[(i + 1) % 3];
    // E(P) = cross(a, b, P), positive inside for positive area; perturbed: E + e*dE/dx + e^2*dE/dy.
    const std::int64_t terms[3] = {cross(a, b, p), -(b.y - a.y), b.x - a.x};
    std::int64_t decided = 0;
    for (std::int64_t term : terms)
      if (term != 0) {
        decided = term * sign;
        break;
      }
    if (decided <= 0) return false;
  }
  return true;
}

std::vector<bool> oracle_mask(const Sub tri[3], std::uint32_t width, std::uint32_t height) {
  std::vector<bool> mask(std::size_t{width} * height);
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x)
      mask[std::size_t{y} * width + x] = oracle_covers(tri, pixel_centre(x, y));
  return mask;
}

// Strictly inside a convex polygon (either winding): on the inner side of every edge.
bool strictly_inside_convex(const std::vector<Sub>& polygon, const Sub& p) {
  int positive = 0, negative = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const std::int64_t e = cross(polygon[i], polygon[(i + 1) % polygon.size()], p);
    positive += e > 0;
    negative += e < 0;
  }
  const int n = static_cast<int>(polygon.size());
  return positive == n || negative == n;
}

std::vector<glm::vec3> world_polygon(const std::vector<Sub>& points, float z = 0.0f) {
  std::vector<glm::vec3> out;
  for (const Sub& p : points) out.push_back(to_world(p, z));
  return out;
}

std::string describe_mismatch(const std::vector<bool>& actual, const std::vector<bool>& expected,
                              std::uint32_t width) {
  std::string text;
  for (std::size_t i = 0; i < actual.size() && text.size() < 400; ++i)
    if (actual[i] != expected[i])
      text += (actual[i] ? " extra(" : " missing(") + std::to_string(i % width) + "," +
              std::to_string(i / width) + ")";
  return text;
}

// For geometry whose winding is not what a test is about.
Lighting no_culling() {
  Lighting lighting;
  lighting.cull_back_faces = false;
  return lighting;
}

// --- Coverage -------------------------------------------------------------------------------

TEST(ZBufferCoverage, HandMadeTrianglesCoverExactlyThePixelCentresInside) {
  const std::uint32_t w = 64, h = 32;
  // Vertices off pixel centres (all exact in 1/256 pixel): thin, wide, partly outside.
  const Sub triangles[][3] = {
      {{544, 992}, {10400, 2384}, {4368, 7376}},
      {{200, 300}, {15000, 900}, {14000, 1500}},       // a sliver
      {{-3000, -700}, {9000, 4000}, {2100, 9999}},     // clipped by the image's top-left corner
      {{12000, 5000}, {19000, 6100}, {16100, 11000}},  // clipped by the right and bottom
      {{7000, 100}, {7100, 8000}, {6900, 8000}},       // tall and one pixel wide
  };
  for (const auto& tri : triangles) {
    const std::vector<bool> expected = oracle_mask(tri, w, h);
    // Both windings, culling off: coverage must not depend on the order of the vertices.
    for (int winding = 0; winding < 2; ++winding) {
      Canvas canvas(pixel_camera(w, h), no_culling());
      const Sub ordered[3] = {tri[0], winding ? tri[2] : tri[1], winding ? tri[1] : tri[2]};
      canvas.draw(world_polygon({ordered[0], ordered[1], ordered[2]}));
      const std::vector<bool> actual = canvas.written_mask();
      EXPECT_EQ(actual, expected) << describe_mismatch(actual, expected, w);
      std::size_t expected_count = 0;
      for (bool b : expected) expected_count += b;
      EXPECT_GT(expected_count, 0u);
      EXPECT_EQ(canvas.renderer.counters().fragments_covered, expected_count);
    }
  }
}

// Edges through pixel centres: only the top-left rule decides. Expected sets counted by hand.
TEST(ZBufferCoverage, PixelCentresOnAnEdgeFollowTheTopLeftRule) {
  const std::uint32_t w = 16, h = 16;
  {
    // Right triangle (2.5, 1.5), (8.5, 1.5), (2.5, 7.5): top edge y = 1.5 and left edge x = 2.5
    // are in; centres on the hypotenuse x + y = 10 are out. So px >= 2, py >= 1, px + py < 9:
    // 6 + 5 + 4 + 3 + 2 + 1 = 21 pixels.
    Canvas canvas(pixel_camera(w, h), no_culling());
    canvas.draw({{2.5f, 1.5f, 0}, {8.5f, 1.5f, 0}, {2.5f, 7.5f, 0}});
    std::vector<bool> expected(w * h);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) expected[y * w + x] = x >= 2 && y >= 1 && x + y < 9;
    EXPECT_EQ(canvas.written_mask(), expected)
        << describe_mismatch(canvas.written_mask(), expected, w);
    EXPECT_EQ(canvas.written_count(), 21u);
  }
  {
    // The other half of the square (2.5 .. 8.5) x (1.5 .. 7.5): its vertical edge is a right
    // edge and its horizontal one a bottom edge, so their centres are out; the shared
    // hypotenuse is now a left edge and its centres are in. So px < 8, py < 7, px + py >= 9:
    // 1 + 2 + 3 + 4 + 5 = 15 pixels, and the two halves together cover the 6 x 6 centres once.
    Canvas canvas(pixel_camera(w, h), no_culling());
    canvas.draw({{8.5f, 7.5f, 0}, {2.5f, 7.5f, 0}, {8.5f, 1.5f, 0}});
    std::vector<bool> expected(w * h);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) expected[y * w + x] = x < 8 && y < 7 && x + y >= 9;
    EXPECT_EQ(canvas.written_mask(), expected)
        << describe_mismatch(canvas.written_mask(), expected, w);
    EXPECT_EQ(canvas.written_count(), 15u);
  }
  {
    // A square from centre (2.5, 1.5) to centre (5.5, 4.5): 4 x 4 centres on or in it, of
    // which the right column and bottom row are out: exactly 3 x 3.
    Canvas canvas(pixel_camera(w, h), no_culling());
    canvas.draw({{2.5f, 1.5f, 0}, {5.5f, 1.5f, 0}, {5.5f, 4.5f, 0}, {2.5f, 4.5f, 0}});
    std::vector<bool> expected(w * h);
    for (int y = 1; y < 4; ++y)
      for (int x = 2; x < 5; ++x) expected[y * w + x] = true;
    EXPECT_EQ(canvas.written_mask(), expected)
        << describe_mismatch(canvas.written_mask(), expected, w);
  }
}

TEST(ZBufferCoverage, RandomTrianglesMatchTheOracleExactly) {
  const std::uint32_t w = 32, h = 16;
  std::mt19937 generator(7);
  auto coordinate = [&](std::int64_t extent, bool on_half_pixels) {
    const std::int64_t r =
        static_cast<std::int64_t>(generator() % (extent * kSubpixel + 2048)) - 1024;
    // On half pixels, many edges pass exactly through pixel centres and vertices sit on them.
    return on_half_pixels ? (r / (kSubpixel / 2)) * (kSubpixel / 2) : r;
  };
  for (int i = 0; i < 400; ++i) {
    const bool on_half_pixels = i % 2 == 1;
    const Sub tri[3] = {{coordinate(w, on_half_pixels), coordinate(h, on_half_pixels)},
                        {coordinate(w, on_half_pixels), coordinate(h, on_half_pixels)},
                        {coordinate(w, on_half_pixels), coordinate(h, on_half_pixels)}};
    Canvas canvas(pixel_camera(w, h), no_culling());
    canvas.draw(world_polygon({tri[0], tri[1], tri[2]}));
    const std::vector<bool> expected = oracle_mask(tri, w, h);
    const std::vector<bool> actual = canvas.written_mask();
    ASSERT_EQ(actual, expected) << "triangle " << i << ":"
                                << describe_mismatch(actual, expected, w);
  }
}

// --- Shared edges: no gaps, no double hits ----------------------------------------------------

// Checks a set of triangles that tile a region: every pixel was hit at most once
// (fragments_covered equals the distinct pixels written), the union is what the per-triangle
// oracle gives, and every pixel centre strictly inside `outline` (convex) is covered.
void expect_tiled_once(const Canvas& canvas, const std::vector<std::array<Sub, 3>>& triangles,
                       const std::function<bool(const Sub&)>& strictly_inside_union) {
  const std::uint32_t w = canvas.renderer.width(), h = canvas.renderer.height();
  std::vector<int> oracle_hits(std::size_t{w} * h, 0);
  for (const auto& tri : triangles) {
    const std::vector<bool> mask = oracle_mask(tri.data(), w, h);
    for (std::size_t i = 0; i < mask.size(); ++i) oracle_hits[i] += mask[i];
  }
  std::size_t gaps = 0, oracle_doubles = 0, inside = 0;
  std::vector<bool> oracle_union(oracle_hits.size());
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::size_t i = std::size_t{y} * w + x;
      oracle_union[i] = oracle_hits[i] > 0;
      oracle_doubles += oracle_hits[i] > 1;
      if (strictly_inside_union(pixel_centre(x, y))) {
        ++inside;
        gaps += !canvas.written(i);
      }
    }
  EXPECT_EQ(oracle_doubles, 0u) << "the oracle itself puts a pixel in two triangles";
  EXPECT_GT(inside, 50u);
  EXPECT_EQ(gaps, 0u);
  EXPECT_EQ(canvas.renderer.counters().fragments_covered, canvas.written_count())
      << "some pixel was covered twice";
  EXPECT_EQ(canvas.written_mask(), oracle_union)
      << describe_mismatch(canvas.written_mask(), oracle_union, w);
}

TEST(ZBufferSharedEdges, ASquareSplitInTwoIsDrawnOnce) {
  // A quadrilateral whose diagonal a-c runs through pixel centres (k + .5, k + .5).
  const Sub a = pixel_centre(3, 3), b{15 * 256 + 64, 4 * 256 + 32}, c = pixel_centre(17, 17),
            d{5 * 256 + 32, 16 * 256 + 192};
  const std::vector<Sub> quad = {a, b, c, d};
  auto inside = [&](const Sub& p) { return strictly_inside_convex(quad, p); };
  {
    Canvas canvas(pixel_camera(32, 32), no_culling());
    canvas.draw(world_polygon({a, b, c}));
    canvas.draw(world_polygon({a, c, d}));
    expect_tiled_once(canvas, {{a, b, c}, {a, c, d}}, inside);
  }
  {
    Canvas canvas(pixel_camera(32, 32), no_culling());  // the same as one polygon: a fan from a
    canvas.draw(world_polygon(quad));
    expect_tiled_once(canvas, {{a, b, c}, {a, c, d}}, inside);
  }
}

TEST(ZBufferSharedEdges, ASevenVertexFanIsDrawnOnce) {
  // A convex heptagon around (20.3, 18.7), radius 13, vertex 0 on a pixel centre and vertex 3
  // chosen so that the fan diagonal 0-3 runs through pixel centres.
  std::vector<Sub> heptagon;
  for (int i = 0; i < 7; ++i) {
    const double angle = 2 * kPi * i / 7;
    heptagon.push_back({std::llround((20.3 + 13 * std::cos(angle)) * kSubpixel),
                        std::llround((18.7 + 13 * std::sin(angle)) * kSubpixel)});
  }
  heptagon[0] = pixel_centre(33, 18);
  heptagon[3] = pixel_centre(9, 24);  // (33.5, 18.5) - (9.5, 24.5): slope -1/4, through centres
  ASSERT_TRUE(strictly_inside_convex(heptagon, pixel_centre(20, 18)));
  std::vector<std::array<Sub, 3>> fan;
  for (int i = 1; i + 1 < 7; ++i) fan.push_back({heptagon[0], heptagon[i], heptagon[i + 1]});
  Canvas canvas(pixel_camera(64, 64), no_culling());
  canvas.draw(world_polygon(heptagon));
  EXPECT_EQ(canvas.renderer.counters().triangles_drawn, 5u);
  expect_tiled_once(canvas, fan, [&](const Sub& p) { return strictly_inside_convex(heptagon, p); });
}

// Point strictly inside a simple polygon (crossing number), false on its boundary.
bool strictly_inside_simple(const std::vector<Sub>& polygon, const Sub& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Sub& a = polygon[j];
    const Sub& b = polygon[i];
    if (cross(a, b, p) == 0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
        std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y))
      return false;  // on the boundary
    if ((a.y > p.y) != (b.y > p.y)) {
      // x of the edge at height p.y compared with p.x, without division.
      const std::int64_t lhs = (p.x - a.x) * (b.y - a.y);
      const std::int64_t rhs = (b.x - a.x) * (p.y - a.y);
      if ((b.y > a.y) ? lhs < rhs : lhs > rhs) inside = !inside;
    }
  }
  return inside;
}

// A 20 x 20 grid of jittered points, 722 triangles, drawn one by one in a shuffled order.
void expect_jittered_grid_tiles(bool on_pixel_centres, std::uint32_t seed) {
  const int n = 20;
  const std::int64_t spacing = 6 * kSubpixel;
  std::mt19937 generator(seed);
  std::vector<Sub> points(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Jitter up to 1.5 pixels: every cell's triangles keep their orientation (checked).
      const auto jitter = [&] { return static_cast<std::int64_t>(generator() % 769) - 384; };
      Sub p{5 * kSubpixel + i * spacing + jitter(), 3 * kSubpixel + j * spacing + jitter()};
      if (on_pixel_centres) p = pixel_centre(p.x / kSubpixel, p.y / kSubpixel);
      points[j * n + i] = p;
    }
  std::vector<std::array<Sub, 3>> triangles;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const Sub p00 = points[j * n + i], p10 = points[j * n + i + 1], p01 = points[(j + 1) * n + i],
                p11 = points[(j + 1) * n + i + 1];
      // Counter-clockwise as seen (front-facing, drawn with culling on, as a mesh would be);
      // alternating diagonals, so edges of both slopes are shared.
      if ((i + j) % 2 == 0) {
        triangles.push_back({p00, p11, p10});
        triangles.push_back({p00, p01, p11});
      } else {
        triangles.push_back({p00, p01, p10});
        triangles.push_back({p10, p01, p11});
      }
    }
  for (const auto& t : triangles) ASSERT_LT(cross(t[0], t[1], t[2]), 0) << "jitter flipped a cell";
  std::shuffle(triangles.begin(), triangles.end(), generator);
  // The outline: the grid's boundary points in order.
  std::vector<Sub> outline;
  for (int i = 0; i < n; ++i) outline.push_back(points[i]);
  for (int j = 1; j < n; ++j) outline.push_back(points[j * n + n - 1]);
  for (int i = n - 2; i >= 0; --i) outline.push_back(points[(n - 1) * n + i]);
  for (int j = n - 2; j >= 1; --j) outline.push_back(points[j * n]);

  Canvas canvas(pixel_camera(128, 128));
  for (const auto& t : triangles) canvas.draw(world_polygon({t[0], t[1], t[2]}));
  EXPECT_EQ(canvas.renderer.counters().triangles_drawn, triangles.size());
  expect_tiled_once(canvas, triangles,
                    [&](const Sub& p) { return strictly_inside_simple(outline, p); });
}

TEST(ZBufferSharedEdges, AJitteredGridOfTrianglesHasNoGapsAndNoDoubleHits) {
  expect_jittered_grid_tiles(false, 11);
}

TEST(ZBufferSharedEdges, AGridWithEveryVertexOnAPixelCentreHasNoGapsAndNoDoubleHits) {
  expect_jittered_grid_tiles(true, 12);
}

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

// --- Camera -----------------------------------------------------------------------------------

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
