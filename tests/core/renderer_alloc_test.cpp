// Proves the renderer allocates nothing, however many polygons it draws: this binary replaces the
// global operator new (as engine_alloc_test does) and counts calls inside a window opened around
// init(), clear() and a million draw_polygon() calls.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "counting_allocator.h"
#include "mvox/camera.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox {
namespace {

using test::AllocationWindow;

TEST(RendererAllocation, TheCounterSeesAnAllocation) {
  AllocationWindow window;
  // The instrument works: otherwise the next test would prove nothing. A direct call, because
  // compilers may elide a new-expression whose result is unused.
  ::operator delete(::operator new(sizeof(int)));
  EXPECT_EQ(window.count(), 1u);
}

// Uniform in [lo, hi) from raw generator bits (no distributions: they may allocate nothing, but
// their output differs between standard libraries).
float uniform(std::mt19937& generator, float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(generator() >> 8) * (1.0f / 16777216.0f);
}

TEST(RendererAllocation, AMillionRandomPolygonsAllocateNothingAndStayInTheWorkspace) {
  const std::uint32_t w = 97, h = 61;  // odd sizes: no padding hides an overrun
  const std::size_t bound = zbuffer_workspace_bytes(w, h);
  ASSERT_EQ(bound, 5u * w * h + ZBufferRenderer::fragment_bytes());
  constexpr std::size_t kGuardBytes = 256;
  std::vector<float> memory((bound + kGuardBytes) / sizeof(float) + 1);
  auto* bytes = reinterpret_cast<unsigned char*>(memory.data());
  std::memset(bytes + bound, 0x5A, memory.size() * sizeof(float) - bound);
  const glm::vec3 box_min(-1, -1, -1), box_max(1, 1, 1);
  std::mt19937 generator(2024);
  std::uint64_t drawn = 0, clipped = 0, culled = 0, fragments = 0;
  for (bool perspective : {false, true}) {
    ViewOptions view;
    view.azimuth_deg = 30;
    view.elevation_deg = 20;
    view.perspective = perspective;
    const Camera camera = fit_camera(box_min, box_max, view, w, h);
    ZBufferRenderer renderer;
    Lighting lighting;
    lighting.cull_back_faces = perspective;  // both paths of the winding test
    std::size_t allocations = 0;
    {
      AllocationWindow window;
      ASSERT_EQ(renderer.init(memory.data(), bound, camera, lighting), Status::ok);
      glm::vec3 positions[20], normals[20];
      for (int p = 0; p < 500000; ++p) {
        // Small polygons anywhere in and around the box; now and then one far outside the
        // guard band or behind the perspective camera, or with an invalid vertex count.
        const unsigned kind = generator() % 64;
        const float reach = kind == 0 ? 1e7f : kind == 1 ? 40.0f : 1.3f;
        const glm::vec3 centre(uniform(generator, -reach, reach), uniform(generator, -reach, reach),
                               uniform(generator, -reach, reach));
        const int count = kind == 2 ? static_cast<int>(generator() % 21) : 3 + generator() % 5;
        for (int i = 0; i < count; ++i) {
          positions[i] =
              centre + glm::vec3(uniform(generator, -0.1f, 0.1f), uniform(generator, -0.1f, 0.1f),
                                 uniform(generator, -0.1f, 0.1f));
          normals[i] = glm::vec3(uniform(generator, -1, 1), uniform(generator, -1, 1),
                                 uniform(generator, -1, 1));
        }
        renderer.draw_polygon(positions, (p & 1) ? normals : nullptr, count);
      }
      drawn += renderer.counters().triangles_drawn + renderer.counters().triangles_hidden;
      clipped += renderer.counters().polygons_clipped;
      culled += renderer.counters().triangles_culled;
      fragments += renderer.counters().fragments_covered;
      renderer.clear();
      allocations = window.count();
    }
    EXPECT_EQ(allocations, 0u) << (perspective ? "perspective" : "orthographic");
  }
  // The run did real work, on every path (drawn or found hidden: rasterised either way).
  EXPECT_GT(drawn, 1000000u);
  EXPECT_GT(clipped, 5000u);
  EXPECT_GT(culled, 100000u);
  EXPECT_GT(fragments, 50000u);  // only polygons that change the picture are shaded
  // Nothing was written past the bound, and the bound is what it was.
  for (std::size_t i = bound; i < memory.size() * sizeof(float); ++i)
    ASSERT_EQ(bytes[i], 0x5A) << "byte " << i - bound << " past the workspace was written";
  EXPECT_EQ(zbuffer_workspace_bytes(w, h), bound);
}

}  // namespace
}  // namespace mvox
