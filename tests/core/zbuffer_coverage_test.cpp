// The renderer's rasterisation (mvox/zbuffer_renderer.h): exact coverage of pixel centres under
// the top-left rule, checked against an oracle written without the renderer's edge biases, and
// shared edges drawn once: no gaps and no double hits where triangles meet.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mvox/zbuffer_renderer.h"
#include "render_canvas.h"

namespace mvox {
namespace {

using test::Canvas;
using test::cross;
using test::kPi;
using test::kSubpixel;
using test::no_culling;
using test::pixel_camera;
using test::Sub;
using test::world_polygon;

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

std::string describe_mismatch(const std::vector<bool>& actual, const std::vector<bool>& expected,
                              std::uint32_t width) {
  std::string text;
  for (std::size_t i = 0; i < actual.size() && text.size() < 400; ++i)
    if (actual[i] != expected[i])
      text += (actual[i] ? " extra(" : " missing(") + std::to_string(i % width) + "," +
              std::to_string(i / width) + ")";
  return text;
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

}  // namespace
}  // namespace mvox
