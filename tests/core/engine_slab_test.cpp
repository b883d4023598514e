// Slab-parallel extraction in the core (Engine::begin_slab, finish_slab): engines that each take
// a slab of consecutive slices give, joined in slab order with their vertex indices moved, the
// output of one engine over the whole volume: the same vertices in the same order, the same
// polygons and the same counters. Random volumes put the surface across every slab boundary.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mvox/engine.h"

namespace mvox {
namespace {

using test::Mesh;
using test::noise_volume;

struct SlabRun {
  Mesh joined;
  EngineCounters counters;  // summed over the slabs as a host would: emitted vertices only
};

// Runs one engine per slab [cuts[k], cuts[k + 1]) and joins their outputs as the engine's
// header says: local index i < shared is the previous slab's last slice's first vertex + i,
// any other i is (vertices before this slab) + i - shared.
SlabRun extract_in_slabs(const test::Volume<std::uint8_t>& volume, double threshold,
                         const std::vector<std::uint32_t>& cuts, const EngineOptions& options) {
  SlabRun run;
  std::uint64_t last_slice_first_vertex = 0;  // global index, of the previous slab's last slice
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const std::uint32_t first = cuts[k], end = cuts[k + 1];
    test::MeshCapture capture;
    test::Workspace workspace(engine_workspace_bytes(volume.width, volume.height, options));
    Engine engine;
    EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), volume.width, volume.height,
                          threshold, options, &capture),
              Status::ok);
    if (first > 0) {
      EXPECT_EQ(engine.begin_slab(test::slice_of(volume, first - 1), first), Status::ok);
    }
    EXPECT_EQ(engine.next_slice(), first);
    const std::uint64_t shared = engine.counters().shared_vertices;
    const std::uint64_t base = run.joined.vertices.size();
    std::uint64_t slab_last_slice_first = 0;  // local index
    for (std::uint32_t z = first; z < end; ++z) {
      slab_last_slice_first = engine.counters().vertices;
      EXPECT_EQ(engine.push_slice(test::slice_of(volume, z)), Status::ok);
    }
    EXPECT_EQ(end == volume.depth ? engine.finish() : engine.finish_slab(), Status::ok);

    const Mesh& local = capture.mesh;
    EXPECT_EQ(local.vertices.size() + shared, engine.counters().vertices);
    run.joined.vertices.insert(run.joined.vertices.end(), local.vertices.begin(),
                               local.vertices.end());
    for (std::vector<std::uint32_t> polygon : local.polygons) {
      for (std::uint32_t& index : polygon)
        index = static_cast<std::uint32_t>(index < shared ? last_slice_first_vertex + index
                                                          : base + index - shared);
      run.joined.polygons.push_back(polygon);
    }
    last_slice_first_vertex = base + slab_last_slice_first - shared;
    const EngineCounters& c = engine.counters();
    run.counters.slices += c.slices;
    run.counters.inner_voxels += c.inner_voxels;
    run.counters.vertices += c.vertices - c.shared_vertices;
    run.counters.polygons += c.polygons;
    for (int size = 0; size <= kMaxPolygonVertices; ++size)
      run.counters.polygons_by_size[size] += c.polygons_by_size[size];
  }
  return run;
}

void expect_slabs_equal_whole(const test::Volume<std::uint8_t>& volume, double threshold,
                              const std::vector<std::uint32_t>& cuts,
                              const EngineOptions& options = {}) {
  EngineCounters whole_counters;
  const Mesh whole = test::extract(volume, threshold, options, &whole_counters);
  const SlabRun slabs = extract_in_slabs(volume, threshold, cuts, options);
  EXPECT_TRUE(test::meshes_identical(whole, slabs.joined));
  EXPECT_EQ(slabs.counters.slices, whole_counters.slices);
  EXPECT_EQ(slabs.counters.inner_voxels, whole_counters.inner_voxels);
  EXPECT_EQ(slabs.counters.vertices, whole_counters.vertices);
  EXPECT_EQ(slabs.counters.polygons, whole_counters.polygons);
  for (int size = 0; size <= kMaxPolygonVertices; ++size)
    EXPECT_EQ(slabs.counters.polygons_by_size[size], whole_counters.polygons_by_size[size]);
  EXPECT_GT(whole.polygons.size(), 50u);
}

// Every way to cut 9 slices into slabs, from one slab to nine: 2^8 cut sets.
TEST(EngineSlabs, EveryCutOfNoiseGivesTheWholeVolumesOutput) {
  const auto volume = noise_volume(37, 11, 9, 5);
  for (std::uint32_t mask = 0; mask < 256; ++mask) {
    std::vector<std::uint32_t> cuts = {0};
    for (std::uint32_t z = 1; z < 9; ++z)
      if (mask >> (z - 1) & 1) cuts.push_back(z);
    cuts.push_back(9);
    SCOPED_TRACE(mask);
    expect_slabs_equal_whole(volume, 128, cuts);
  }
}

TEST(EngineSlabs, EveryMethodKindAndRuleJoinsToTheWholeVolume) {
  const auto volume = noise_volume(70, 13, 12, 8);  // rows over a 64-bit word
  const std::vector<std::uint32_t> cuts = {0, 1, 4, 5, 11, 12};
  EngineOptions literal;
  literal.kind = EngineKind::literal;
  EngineOptions table1;
  table1.rule = SurfaceRule::paper_table1;
  EngineOptions literal_table1 = table1;
  literal_table1.kind = EngineKind::literal;
  EngineOptions cubes;
  cubes.method = SurfaceMethod::cubes;
  EngineOptions tiny_batches;
  tiny_batches.vertices_per_batch = 1;
  tiny_batches.polygons_per_batch = 3;
  tiny_batches.polygon_geometry = true;
  EngineOptions interpolated;
  interpolated.interpolate = true;  // needs the previous slab's last samples
  EngineOptions literal_interpolated = literal;
  literal_interpolated.interpolate = true;
  for (const EngineOptions& options : {EngineOptions{}, literal, table1, literal_table1, cubes,
                                       tiny_batches, interpolated, literal_interpolated}) {
    expect_slabs_equal_whole(volume, 100, cuts, options);
  }
}

TEST(EngineSlabs, ASlabBoundaryOnAnEmptySliceOrAFullOneStillJoins) {
  test::Volume<std::uint8_t> volume(20, 9, 8);
  for (std::uint32_t z = 0; z < 8; ++z)
    for (std::uint32_t y = 0; y < 9; ++y)
      for (std::uint32_t x = 0; x < 20; ++x)
        volume.at(x, y, z) = z == 3 ? 0 : z == 5 ? 255 : static_cast<std::uint8_t>((x * 7 + y * 3 + z * 11) % 256);
  expect_slabs_equal_whole(volume, 120, {0, 3, 4, 5, 6, 8});
}

TEST(EngineSlabs, BeginSlabIsRefusedOutOfPlace) {
  const auto volume = noise_volume(8, 8, 4, 1);
  test::MeshCapture capture;
  test::Workspace workspace(engine_workspace_bytes(8, 8, {}));
  Engine engine;
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 8, 8, 100, {}, &capture),
            Status::ok);
  EXPECT_EQ(engine.begin_slab(test::slice_of(volume, 0), 0), Status::invalid_argument);
  ASSERT_EQ(engine.push_slice(test::slice_of(volume, 0)), Status::ok);
  EXPECT_EQ(engine.begin_slab(test::slice_of(volume, 0), 1), Status::invalid_argument);

  Engine fresh;
  ASSERT_EQ(fresh.init(workspace.data(), workspace.bytes(), 8, 8, 100, {}, &capture), Status::ok);
  ASSERT_EQ(fresh.begin_slab(test::slice_of(volume, 1), 2), Status::ok);
  EXPECT_EQ(fresh.begin_slab(test::slice_of(volume, 1), 2), Status::invalid_argument);
  EXPECT_EQ(fresh.finish_slab(), Status::ok);
  EXPECT_EQ(fresh.push_slice(test::slice_of(volume, 2)), Status::already_finished);

  Engine unstarted;
  EXPECT_EQ(unstarted.begin_slab(test::slice_of(volume, 1), 2), Status::not_initialised);
}

}  // namespace
}  // namespace mvox
