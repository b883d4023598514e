// Vertex indices past 2^32 (mvox/mesh.h): the engine numbers vertices without limit and a
// polygon carries each index modulo 2^32; whole_vertex_index() gives a sink the whole index
// back from the count of vertices it has taken. Checked on the arithmetic, and on the engine
// numbering from just below 2^32 (detail::number_vertices_from), on every engine path, where
// the whole indices must be the ones of a run from 0, moved by the start.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "mesh_capture.h"
#include "mvox/engine.h"
#include "mvox/mesh.h"
#include "mvox/workspace_buffer.h"

namespace mvox {
namespace {

constexpr std::uint64_t k2to32 = std::uint64_t{1} << 32;

TEST(WholeVertexIndex, GivesBackEveryIndexAmongTheLast2To32Taken) {
  for (const std::uint64_t taken : {std::uint64_t{1}, std::uint64_t{5}, k2to32 - 1, k2to32,
                                    k2to32 + 7, (std::uint64_t{1} << 40) + 3}) {
    for (const std::uint64_t back :
         {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{1000}, k2to32 - 1}) {
      if (back >= taken) continue;
      const std::uint64_t index = taken - 1 - back;
      EXPECT_EQ(whole_vertex_index(static_cast<std::uint32_t>(index), taken), index)
          << "taken " << taken << ", back " << back;
    }
  }
  // Below 2^32 an index not yet taken comes out at or above the count, so it can be refused.
  EXPECT_GE(whole_vertex_index(10, 10), 10u);
  EXPECT_GE(whole_vertex_index(0xFFFFFFFFu, 10), 10u);
}

// Keeps every polygon's whole indices, counting vertices from `first`.
class WholeIndexCapture : public PolygonSink {
 public:
  explicit WholeIndexCapture(std::uint64_t first) : taken_(first) {}
  Status consume_vertices(const Vertex*, std::size_t count) override {
    taken_ += count;
    return Status::ok;
  }
  Status consume_polygons(const Polygon* polygons, std::size_t count) override {
    for (std::size_t i = 0; i < count; ++i)
      for (int k = 0; k < polygons[i].vertex_count; ++k)
        indices.push_back(whole_vertex_index(polygons[i].vertices[k], taken_));
    return Status::ok;
  }
  std::vector<std::uint64_t> indices;

 private:
  std::uint64_t taken_;
};

std::vector<std::uint64_t> whole_indices(const test::BinaryVolume& volume,
                                         const EngineOptions& options, std::uint64_t first,
                                         EngineCounters* counters) {
  WorkspaceBuffer workspace(engine_workspace_bytes(volume.width, volume.height, options));
  WholeIndexCapture capture(first);
  Engine engine;
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), volume.width, volume.height, 128,
                        options, &capture),
            Status::ok);
  detail::number_vertices_from(engine, first);
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    EXPECT_EQ(engine.push_slice(test::slice_of(volume, z)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  *counters = engine.counters();
  return capture.indices;
}

TEST(WholeVertexIndex, TheEngineNumbersOnPast2To32OnEveryPath) {
  const test::BinaryVolume noise = test::noise_volume(37, 29, 23, 3);
  EngineOptions fast, literal, cubes;
  literal.kind = EngineKind::literal;
  cubes.method = SurfaceMethod::cubes;
  for (const EngineOptions& options : {fast, literal, cubes}) {
    EngineCounters from_zero, from_high;
    const std::vector<std::uint64_t> reference = whole_indices(noise, options, 0, &from_zero);
    ASSERT_GT(from_zero.vertices, 20000u);
    // Starting 10,000 below 2^32: the run crosses it, and indices wrap in the polygons.
    const std::uint64_t first = k2to32 - 10000;
    const std::vector<std::uint64_t> moved = whole_indices(noise, options, first, &from_high);
    EXPECT_EQ(from_high.vertices, first + from_zero.vertices);
    ASSERT_EQ(moved.size(), reference.size());
    std::size_t past = 0;
    for (std::size_t i = 0; i < moved.size(); ++i) {
      EXPECT_EQ(moved[i], reference[i] + first) << "index " << i;
      past += moved[i] >= k2to32;
      if (::testing::Test::HasFailure()) break;
    }
    EXPECT_GT(past, 1000u) << "the run never passed 2^32";
  }
}

}  // namespace
}  // namespace mvox
