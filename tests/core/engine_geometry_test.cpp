// Polygons sent by value (EngineOptions::polygon_geometry in mvox/engine.h): every geometry batch
// equals its polygon batch, none without the option, a sink refusing them; and the hot loops
// chosen for this CPU against the baseline ones, batch for batch.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mvox/engine.h"
#include "phantom_factory.h"

namespace mvox {
namespace {

using test::BinaryVolume;
using test::extract;
using test::Mesh;
using test::noise_volume;
using test::slice_of;
using test::Workspace;

// --- EngineOptions::polygon_geometry --------------------------------------------------------

// Captures the indexed output like MeshCapture and checks every polygon-geometry batch against
// the polygon batch that came just before it, its vertices looked up in the vertex stream.
class GeometryCheckingSink final : public test::MeshCapture {
 public:
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    out_of_order += awaiting_geometry_;  // the geometry of the last polygon batch never came
    return MeshCapture::consume_vertices(vertices, vertex_count);
  }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    out_of_order += awaiting_geometry_;
    awaiting_geometry_ = true;
    pending_.assign(polygons, polygons + polygon_count);
    return MeshCapture::consume_polygons(polygons, polygon_count);
  }
  Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                  std::size_t polygon_count) override {
    ++geometry_batches;
    out_of_order += !awaiting_geometry_;
    awaiting_geometry_ = false;
    geometry_polygons += polygon_count;
    if (polygon_count != pending_.size()) {
      ++mismatches;
      return Status::ok;
    }
    for (std::size_t p = 0; p < polygon_count; ++p) {
      const Polygon& indexed = pending_[p];
      const PolygonGeometry& by_value = polygons[p];
      if (by_value.vertex_count != indexed.vertex_count) {
        ++mismatches;
        continue;
      }
      for (int i = 0; i < indexed.vertex_count; ++i) {
        const Vertex& expected = mesh.vertices.at(indexed.vertices[i]);
        const Vertex& actual = by_value.vertices[i];
        // Exact: the engine computes both from the same cube, nothing is rounded differently.
        mismatches += actual.x != expected.x || actual.y != expected.y || actual.z != expected.z ||
                      actual.axis != expected.axis ||
                      actual.inner_is_lower != expected.inner_is_lower;
      }
    }
    return geometry_batches == refuse_geometry_batch ? Status::sink_refused : Status::ok;
  }
  bool awaiting_geometry() const { return awaiting_geometry_; }

  std::size_t geometry_batches = 0;
  std::size_t geometry_polygons = 0;
  std::size_t mismatches = 0;
  std::size_t out_of_order = 0;
  std::size_t refuse_geometry_batch = 0;  // 1-based; 0: refuse none

 private:
  std::vector<Polygon> pending_;
  bool awaiting_geometry_ = false;
};

// Runs the engine with polygon_geometry over `volume` for every engine kind and surface rule of
// marching voxels, and for marching cubes, with two batch sizes; each geometry batch must equal
// its polygon batch by value, and the indexed output must be what it is without the option.
void expect_geometry_equals_indexed_polygons(const BinaryVolume& volume, const std::string& label,
                                             double threshold = 1) {
  struct Variant {
    SurfaceMethod method;
    EngineKind kind;
    SurfaceRule rule;
  };
  const Variant variants[] = {
      {SurfaceMethod::voxels, EngineKind::fast, SurfaceRule::merge_rules},
      {SurfaceMethod::voxels, EngineKind::fast, SurfaceRule::paper_table1},
      {SurfaceMethod::voxels, EngineKind::literal, SurfaceRule::merge_rules},
      {SurfaceMethod::voxels, EngineKind::literal, SurfaceRule::paper_table1},
      {SurfaceMethod::cubes, EngineKind::fast, SurfaceRule::merge_rules}};
  for (const Variant& variant : variants)
    for (std::uint32_t batch : {4096u, 3u}) {
      const EngineKind kind = variant.kind;
      const SurfaceRule rule = variant.rule;
      EngineOptions options;
      options.method = variant.method;
      options.kind = kind;
      options.rule = rule;
      options.vertices_per_batch = batch == 3 ? 5 : batch;
      options.polygons_per_batch = batch;
      const Mesh plain = extract(volume, threshold, options);
      options.polygon_geometry = true;
      GeometryCheckingSink sink;
      Workspace workspace(engine_workspace_bytes(volume.width, volume.height, options));
      Engine engine;
      ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), volume.width, volume.height,
                            threshold, options, &sink),
                Status::ok);
      for (std::uint32_t z = 0; z < volume.depth; ++z)
        ASSERT_EQ(engine.push_slice(slice_of(volume, z)), Status::ok);
      ASSERT_EQ(engine.finish(), Status::ok);
      const std::string where = label +
                                (variant.method == SurfaceMethod::cubes ? " cubes" : " voxels") +
                                (kind == EngineKind::fast ? " fast" : " literal") +
                                (rule == SurfaceRule::merge_rules ? " merge_rules" : " table1") +
                                " batch " + std::to_string(batch);
      EXPECT_GT(sink.mesh.polygons.size(), 0u) << where;
      EXPECT_EQ(sink.mismatches, 0u) << where;
      EXPECT_EQ(sink.out_of_order, 0u) << where;
      EXPECT_FALSE(sink.awaiting_geometry()) << where;
      EXPECT_EQ(sink.geometry_batches, sink.polygon_batches) << where;
      EXPECT_EQ(sink.geometry_polygons, sink.mesh.polygons.size()) << where;
      EXPECT_TRUE(test::meshes_identical(sink.mesh, plain)) << where;
    }
}

BinaryVolume classified(const sim::Phantom& phantom, double density_threshold) {
  const sim::Grid grid = phantom.grid();
  BinaryVolume volume(grid.width, grid.height, grid.depth);
  const std::vector<float> densities = sim::sample_volume(phantom);
  for (std::size_t i = 0; i < densities.size(); ++i)
    volume.samples[i] = densities[i] >= density_threshold;
  return volume;
}

TEST(EngineGeometry, EveryGeometryBatchIsItsPolygonBatchByValue) {
  const sim::Grid grids[] = {{19, 17, 15}, {24, 22, 12}, {26, 23, 21}, {21, 18, 16}};
  const char* names[] = {"sphere", "torus", "shepp-logan", "blobs"};
  for (int i = 0; i < 4; ++i) {
    const auto phantom = sim::make_phantom(names[i], grids[i], 3);
    expect_geometry_equals_indexed_polygons(
        classified(*phantom, sim::default_density_threshold(names[i])), names[i]);
  }
  // Odd-sized noise: every cube configuration, small enough to look at when it fails.
  auto noise = noise_volume(7, 5, 6, 17);
  // Unclassified: marching cubes' vertices then sit anywhere along their edges.
  expect_geometry_equals_indexed_polygons(noise, "noise 0..255 7x5x6", 128);
  for (auto& sample : noise.samples) sample = sample >= 128;
  expect_geometry_equals_indexed_polygons(noise, "noise 7x5x6");
}

TEST(EngineGeometry, WithoutTheOptionNoGeometryIsSent) {
  const auto phantom = sim::make_phantom("sphere", {12, 11, 10}, 0);
  GeometryCheckingSink sink;
  const EngineOptions options;
  ASSERT_FALSE(options.polygon_geometry);  // off by default
  Workspace workspace(engine_workspace_bytes(12, 11, options));
  Engine engine;
  const BinaryVolume volume = classified(*phantom, 0.5);
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 12, 11, 1, options, &sink),
            Status::ok);
  for (std::uint32_t z = 0; z < 10; ++z)
    ASSERT_EQ(engine.push_slice(slice_of(volume, z)), Status::ok);
  ASSERT_EQ(engine.finish(), Status::ok);
  EXPECT_GT(sink.mesh.polygons.size(), 0u);
  EXPECT_EQ(sink.geometry_batches, 0u);
}

TEST(EngineGeometry, ASinkRefusingGeometryStopsTheEngine) {
  const auto phantom = sim::make_phantom("torus", {24, 22, 12}, 0);
  const BinaryVolume volume = classified(*phantom, 0.5);
  EngineOptions options;
  options.polygon_geometry = true;
  options.polygons_per_batch = 10;
  GeometryCheckingSink sink;
  sink.refuse_geometry_batch = 2;
  Workspace workspace(engine_workspace_bytes(24, 22, options));
  Engine engine;
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 24, 22, 1, options, &sink),
            Status::ok);
  Status status = Status::ok;
  for (std::uint32_t z = 0; z < volume.depth && status == Status::ok; ++z)
    status = engine.push_slice(slice_of(volume, z));
  EXPECT_EQ(status, Status::sink_refused);
  EXPECT_EQ(engine.finish(), Status::sink_refused);
  EXPECT_EQ(sink.geometry_batches, 2u);
  EXPECT_EQ(sink.polygon_batches, 2u);  // nothing after the refusal
  EXPECT_EQ(sink.mismatches, 0u);
}

// ---------------------------------------------------------------------------------------------
// The hot loops chosen for this CPU (AVX2 on x86-64 that has it, cpu_features.h) against the
// baseline ones any CPU runs (detail::use_baseline_loops): byte for byte the same batches.

// Every batch as the sink received it: its size, and each vertex's and polygon's fields.
class BatchRecorder final : public PolygonSink {
 public:
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    batches.push_back(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) {
      const Vertex& v = vertices[i];
      append(&v.x, sizeof v.x);
      append(&v.y, sizeof v.y);
      append(&v.z, sizeof v.z);
      append(&v.axis, sizeof v.axis);
      append(&v.inner_is_lower, sizeof v.inner_is_lower);
    }
    return Status::ok;
  }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    batches.push_back(~polygon_count);  // told apart from vertex batches
    for (std::size_t i = 0; i < polygon_count; ++i) {
      append(&polygons[i].vertex_count, 1);
      append(polygons[i].vertices, polygons[i].vertex_count * sizeof(std::uint32_t));
    }
    return Status::ok;
  }
  std::vector<std::size_t> batches;
  std::vector<unsigned char> bytes;

 private:
  void append(const void* data, std::size_t size) {
    const auto* begin = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), begin, begin + size);
  }
};

BatchRecorder record_batches(const BinaryVolume& volume, const EngineOptions& options,
                             bool baseline) {
  BatchRecorder sink;
  Workspace workspace(engine_workspace_bytes(volume.width, volume.height, options));
  Engine engine;
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), volume.width, volume.height, 1,
                        options, &sink),
            Status::ok);
  if (baseline) detail::use_baseline_loops(engine);
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    EXPECT_EQ(engine.push_slice(slice_of(volume, z)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  return sink;
}

void expect_same_batches_on_both_paths(const BinaryVolume& volume, const std::string& label) {
  EngineOptions tiny;
  tiny.vertices_per_batch = 7;
  tiny.polygons_per_batch = 5;
  EngineOptions table1;
  table1.rule = SurfaceRule::paper_table1;
  EngineOptions cubes;
  cubes.method = SurfaceMethod::cubes;
  for (const EngineOptions& options : {EngineOptions(), tiny, table1, cubes}) {
    const BatchRecorder chosen = record_batches(volume, options, false);
    const BatchRecorder baseline = record_batches(volume, options, true);
    EXPECT_FALSE(baseline.bytes.empty()) << label;
    EXPECT_EQ(chosen.batches, baseline.batches) << label;
    EXPECT_TRUE(chosen.bytes == baseline.bytes) << label;
  }
}

TEST(EngineDispatch, TheLoopsChosenForThisCpuGiveTheBaselineBatches) {
  std::uint32_t seed = 100;
  for (std::uint32_t width : {1u, 62u, 63u, 64u, 65u, 130u, 200u})
    for (int density : {30, 128, 230}) {
      auto noise = noise_volume(width, 9, 7, seed++);
      for (auto& sample : noise.samples) sample = sample < density;
      expect_same_batches_on_both_paths(
          noise, "noise " + std::to_string(width) + " density " + std::to_string(density));
    }
  const char* names[] = {"sphere", "torus", "shepp-logan", "blobs"};
  for (const char* name : names) {
    const auto phantom = sim::make_phantom(name, {70, 66, 20}, 3);
    expect_same_batches_on_both_paths(classified(*phantom, sim::default_density_threshold(name)),
                                      name);
  }
}

}  // namespace
}  // namespace mvox
