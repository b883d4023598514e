// The engine's contract: workspace bound, statuses, sample types and thresholds, batching, and
// polygons sent by value (EngineOptions::polygon_geometry).
#include "mvox/engine.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mvox/counting_sink.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "phantom_factory.h"

namespace mvox {
namespace {

using test::BinaryVolume;
using test::extract;
using test::Mesh;
using test::Workspace;

// A reproducible volume of 8-bit samples 0..255 (raw generator bits; no distributions, whose
// output differs between standard libraries).
test::Volume<std::uint8_t> noise_volume(std::uint32_t w, std::uint32_t h, std::uint32_t d,
                                        std::uint32_t seed) {
  test::Volume<std::uint8_t> volume(w, h, d);
  std::mt19937 generator(seed);
  for (auto& sample : volume.samples) sample = static_cast<std::uint8_t>(generator() >> 24);
  return volume;
}

SliceView slice_of(const BinaryVolume& volume, std::uint32_t z) {
  SliceView slice;
  slice.samples = volume.samples.data() + std::size_t{z} * volume.width * volume.height;
  slice.width = volume.width;
  slice.height = volume.height;
  slice.row_stride_bytes = volume.width;
  return slice;
}

TEST(EngineWorkspace, EverySizeBelowTheBoundIsRefusedAndTheBoundItselfWorks) {
  const std::uint32_t sizes[][2] = {{1, 1}, {3, 2}, {7, 5}, {62, 3}, {63, 2}, {64, 1}, {130, 4}};
  for (EngineKind kind : {EngineKind::fast, EngineKind::literal}) {
    EngineOptions options;
    options.kind = kind;
    options.vertices_per_batch = 7;
    options.polygons_per_batch = 5;
    for (const auto& size : sizes) {
      const std::size_t bound = engine_workspace_bytes(size[0], size[1], options);
      ASSERT_GT(bound, 0u);
      Workspace workspace(bound);
      CountingSink sink;
      Engine engine;
      for (std::size_t bytes = 0; bytes < bound; ++bytes)
        ASSERT_EQ(engine.init(workspace.data(), bytes, size[0], size[1], 1, options, &sink),
                  Status::workspace_too_small)
            << size[0] << "x" << size[1] << " with " << bytes << " of " << bound << " bytes";
      ASSERT_EQ(engine.init(workspace.data(), bound, size[0], size[1], 1, options, &sink),
                Status::ok);
      // The bound is enough for a real run, not just for init(): a full slice then finish.
      std::vector<std::uint8_t> full(std::size_t{size[0]} * size[1], 1);
      SliceView slice{full.data(), size[0], size[1], size[0], SampleType::u8};
      EXPECT_EQ(engine.push_slice(slice), Status::ok);
      EXPECT_EQ(engine.finish(), Status::ok);
      EXPECT_EQ(sink.polygons, engine.counters().polygons);
      EXPECT_GT(sink.polygons, 0u);
    }
  }
}

TEST(EngineWorkspace, BoundGrowsWithTheSlice) {
  const EngineOptions options;
  const std::size_t small = engine_workspace_bytes(256, 256, options);
  EXPECT_LT(small, engine_workspace_bytes(512, 256, options));
  EXPECT_LT(small, engine_workspace_bytes(256, 512, options));
  // About 0.25 bytes per pixel plus the batch buffers: a 2048x2048 micro-CT slice needs < 2 MiB.
  EXPECT_LT(engine_workspace_bytes(2048, 2048, options), std::size_t{2} << 20);
  EngineOptions literal = options;
  literal.kind = EngineKind::literal;
  EXPECT_GT(engine_workspace_bytes(256, 256, literal), small);
}

// README.md states the workspace as a formula; keep the two in step. The remainder is the
// engine's state struct and the 16-byte alignment of each buffer.
TEST(EngineWorkspace, MatchesTheFormulaInTheReadme) {
  EngineOptions options;
  EngineOptions literal;
  literal.kind = EngineKind::literal;
  const std::uint32_t sizes[][2] = {{1, 1}, {7, 5}, {256, 256}, {513, 300}, {2048, 2048}};
  for (const auto& size : sizes) {
    const std::size_t w = size[0], h = size[1];
    const std::size_t words = (w + 2 + 63) / 64;
    const std::size_t formula = words * (16 * h + 8) + 2 * h + 16 * 4096 + 32 * 4096;
    const std::size_t actual = engine_workspace_bytes(size[0], size[1], options);
    EXPECT_GE(actual, formula) << w << "x" << h;
    EXPECT_LE(actual, formula + 512) << w << "x" << h;
    // The literal engine adds its edge planes (60 bytes per 64 voxels of a row, plus the extra
    // row of y-edges) and 2 * 49 bytes per cube of a layer for its merge state.
    const std::size_t literal_extra = engine_workspace_bytes(size[0], size[1], literal) - actual;
    const std::size_t literal_formula = words * (60 * h + 24) + 98 * (w + 1) * (h + 1);
    EXPECT_GE(literal_extra, literal_formula) << w << "x" << h;
    EXPECT_LE(literal_extra, literal_formula + 64) << w << "x" << h;
  }
}

TEST(EngineWorkspace, InvalidArgumentsAreRefused) {
  EngineOptions options;
  EXPECT_EQ(engine_workspace_bytes(0, 5, options), 0u);
  EXPECT_EQ(engine_workspace_bytes(5, 0, options), 0u);
  EXPECT_EQ(engine_workspace_bytes(100000, 100000, options), 0u);  // plane counters would overflow
  // Dimensions whose +1 or +2 wraps in 32 bits must not slip through as small workspaces.
  const std::uint32_t most = 0xFFFFFFFFu;
  for (const auto& size : {std::pair{most, 1u}, std::pair{most - 1, 3u}, std::pair{1u, most},
                           std::pair{most, most}, std::pair{3u, most - 1}})
    EXPECT_EQ(engine_workspace_bytes(size.first, size.second, options), 0u)
        << size.first << "x" << size.second;
  Workspace workspace(engine_workspace_bytes(4, 4, options) + 64);
  CountingSink sink;
  Engine engine;
  EXPECT_EQ(engine.init(nullptr, 1 << 20, 4, 4, 1, options, &sink), Status::invalid_argument);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, 1, options, nullptr),
            Status::invalid_argument);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, std::nan(""), options, &sink),
            Status::invalid_argument);
  char* misaligned = static_cast<char*>(workspace.data()) + kWorkspaceAlignment / 2;
  EXPECT_EQ(
      engine.init(misaligned, workspace.bytes() - kWorkspaceAlignment, 4, 4, 1, options, &sink),
      Status::workspace_misaligned);
  options.polygons_per_batch = 0;
  EXPECT_EQ(engine_workspace_bytes(4, 4, options), 0u);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, 1, options, &sink),
            Status::invalid_argument);
}

TEST(EngineLifecycle, CallsOutOfOrderAndWrongSlicesAreRefusedWithAStatus) {
  const BinaryVolume volume = test::volume_from_bits(3, 2, 2, 0b101101011011);
  const EngineOptions options;
  Workspace workspace(engine_workspace_bytes(3, 2, options));
  CountingSink sink;
  Engine engine;
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::not_initialised);
  EXPECT_EQ(engine.finish(), Status::not_initialised);
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 3, 2, 1, options, &sink), Status::ok);

  SliceView wrong = slice_of(volume, 0);
  wrong.width = 2;
  wrong.row_stride_bytes = 3;
  EXPECT_EQ(engine.push_slice(wrong), Status::slice_size_mismatch);
  SliceView short_stride = slice_of(volume, 0);
  short_stride.row_stride_bytes = 2;
  EXPECT_EQ(engine.push_slice(short_stride), Status::invalid_argument);
  SliceView null_samples = slice_of(volume, 0);
  null_samples.samples = nullptr;
  EXPECT_EQ(engine.push_slice(null_samples), Status::invalid_argument);
  SliceView unknown_type = slice_of(volume, 0);
  unknown_type.type = static_cast<SampleType>(9);
  EXPECT_EQ(engine.push_slice(unknown_type), Status::invalid_argument);
  EXPECT_EQ(engine.counters().slices, 0u);  // refused slices leave the engine as it was

  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 1)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::already_finished);
  EXPECT_EQ(engine.finish(), Status::already_finished);
  // The refused calls changed nothing: the output equals a clean run's.
  EXPECT_EQ(sink.polygons, extract(volume, 1).polygons.size());

  // init() starts a new volume on the same workspace.
  CountingSink second;
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 3, 2, 1, options, &second),
            Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 1)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  EXPECT_EQ(second.polygons, sink.polygons);
  EXPECT_EQ(second.vertices, sink.vertices);
}

TEST(EngineLifecycle, ASinkThatRefusesStopsTheEngineAndReceivesNothingMore) {
  const auto volume = noise_volume(20, 17, 9, 7);
  EngineOptions options;
  options.vertices_per_batch = 16;
  options.polygons_per_batch = 16;
  for (std::size_t refuse_at : {1, 2, 5, 40}) {
    Workspace workspace(engine_workspace_bytes(20, 17, options));
    CountingSink sink;
    sink.refuse_batch = refuse_at;
    Engine engine;
    ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 20, 17, 128, options, &sink),
              Status::ok);
    Status last = Status::ok;
    for (std::uint32_t z = 0; z < 9 && last == Status::ok; ++z) {
      SliceView slice{volume.samples.data() + z * 20 * 17, 20, 17, 20, SampleType::u8};
      last = engine.push_slice(slice);
    }
    if (last == Status::ok) last = engine.finish();
    EXPECT_EQ(last, Status::sink_refused) << "refusing batch " << refuse_at;
    EXPECT_EQ(sink.batches, refuse_at) << "batches arrived after the refusal";
    SliceView slice{volume.samples.data(), 20, 17, 20, SampleType::u8};
    EXPECT_EQ(engine.push_slice(slice), Status::sink_refused);
    EXPECT_EQ(engine.finish(), Status::sink_refused);
    EXPECT_EQ(sink.batches, refuse_at);
  }
}

TEST(EngineSamples, AllSampleTypesGiveTheSameSurfaceForTheSameClassification) {
  const auto bytes = noise_volume(13, 11, 7, 3);
  const Mesh reference = extract(bytes, 100);
  test::Volume<std::uint16_t> wide(13, 11, 7);
  test::Volume<std::int16_t> signed_samples(13, 11, 7);
  test::Volume<float> real(13, 11, 7);
  for (std::size_t i = 0; i < bytes.samples.size(); ++i) {
    wide.samples[i] = static_cast<std::uint16_t>(bytes.samples[i] * 257);  // 0..65535
    signed_samples.samples[i] = static_cast<std::int16_t>((bytes.samples[i] - 128) * 256);
    real.samples[i] = static_cast<float>(bytes.samples[i]) / 255.0f;
  }
  EXPECT_TRUE(test::meshes_identical(reference, extract(wide, 100 * 257)));
  EXPECT_TRUE(test::meshes_identical(reference, extract(signed_samples, (100 - 128) * 256)));
  EXPECT_TRUE(test::meshes_identical(reference, extract(real, 100 / 255.0f)));
  EXPECT_GT(reference.polygons.size(), 100u);
}

TEST(EngineSamples, AVoxelIsInnerExactlyWhenItsSampleIsAtLeastTheThreshold) {
  auto count_inner = [](auto volume, double threshold) {
    EngineCounters counters;
    extract(volume, threshold, {}, &counters);
    return counters.inner_voxels;
  };
  test::Volume<std::uint8_t> bytes(3, 1, 1);
  bytes.samples = {99, 100, 101};
  EXPECT_EQ(count_inner(bytes, 100), 2u);    // equal counts as inner
  EXPECT_EQ(count_inner(bytes, 100.5), 1u);  // fractional thresholds round up for integers
  EXPECT_EQ(count_inner(bytes, 99.0001), 2u);
  EXPECT_EQ(count_inner(bytes, -5), 3u);   // below the type's range: everything inner
  EXPECT_EQ(count_inner(bytes, 300), 0u);  // above: nothing
  test::Volume<std::int16_t> signed_samples(3, 1, 1);
  signed_samples.samples = {-1025, -1024, 32767};
  EXPECT_EQ(count_inner(signed_samples, -1024), 2u);
  test::Volume<float> real(4, 1, 1);
  real.samples = {0.1f, std::nextafter(0.1f, 0.0f), std::numeric_limits<float>::quiet_NaN(), 1e30f};
  // 0.1f is slightly above 0.1: inner at 0.1, outer at a threshold just above it.
  EXPECT_EQ(count_inner(real, 0.1), 2u);
  EXPECT_EQ(count_inner(real, static_cast<double>(0.1f) + 1e-12), 1u);
  EXPECT_EQ(count_inner(real, -1e300), 3u);  // NaN is never inner
  // Thresholds beyond the float range, and infinities.
  test::Volume<float> extremes(4, 1, 1);
  extremes.samples = {-INFINITY, -FLT_MAX, FLT_MAX, INFINITY};
  EXPECT_EQ(count_inner(extremes, -INFINITY), 4u);
  EXPECT_EQ(count_inner(extremes, -1e300), 3u);
  EXPECT_EQ(count_inner(extremes, 1e300), 1u);
  EXPECT_EQ(count_inner(extremes, INFINITY), 1u);
  EXPECT_EQ(count_inner(extremes, static_cast<double>(FLT_MAX)), 2u);
}

TEST(EngineOutput, BatchSizesAndRowStridesDoNotChangeTheOutput) {
  const auto volume = noise_volume(70, 9, 8, 11);  // wider than one 64-bit word
  const Mesh reference = extract(volume, 128);
  EngineOptions tiny;
  tiny.vertices_per_batch = 1;
  tiny.polygons_per_batch = 1;
  EXPECT_TRUE(test::meshes_identical(reference, extract(volume, 128, tiny)));
  tiny.vertices_per_batch = 3;
  tiny.polygons_per_batch = 64;
  EXPECT_TRUE(test::meshes_identical(reference, extract(volume, 128, tiny)));

  // The same slices inside wider rows (a region of a larger image).
  const std::uint32_t stride = 83;
  std::vector<std::uint8_t> padded(std::size_t{stride} * 9 * 8, 255);
  for (std::uint32_t z = 0; z < 8; ++z)
    for (std::uint32_t y = 0; y < 9; ++y)
      std::memcpy(&padded[(std::size_t{z} * 9 + y) * stride], &volume.samples[(z * 9 + y) * 70],
                  70);
  std::vector<SliceView> slices;
  for (std::uint32_t z = 0; z < 8; ++z)
    slices.push_back({&padded[std::size_t{z} * 9 * stride], 70, 9, stride, SampleType::u8});
  EXPECT_TRUE(test::meshes_identical(reference, test::extract_slices(slices, 70, 9, 128)));
}

TEST(EngineOutput, MisalignedSamplesAndStridesGiveTheSameSurface) {
  const auto bytes = noise_volume(13, 11, 7, 21);
  test::Volume<std::uint16_t> wide(13, 11, 7);
  for (std::size_t i = 0; i < bytes.samples.size(); ++i) wide.samples[i] = bytes.samples[i] * 3u;
  const Mesh reference = extract(wide, 300);
  // The same samples one byte into a buffer, rows 27 bytes apart: nothing is aligned.
  const std::size_t stride = 27;
  std::vector<unsigned char> buffer(1 + stride * 11 * 7);
  for (std::uint32_t z = 0; z < 7; ++z)
    for (std::uint32_t y = 0; y < 11; ++y)
      std::memcpy(&buffer[1 + (z * 11 + y) * stride], &wide.samples[(z * 11 + y) * 13], 26);
  std::vector<SliceView> slices;
  for (std::uint32_t z = 0; z < 7; ++z)
    slices.push_back({&buffer[1 + z * 11 * stride], 13, 11, stride, SampleType::u16});
  EXPECT_TRUE(test::meshes_identical(reference, test::extract_slices(slices, 13, 11, 300)));
}

// Widths around the 64-bit words that hold a padded row (width + 2 bits), where carries between
// words matter; both engines, against the vertex oracle, closed and consistently wound.
TEST(EngineOutput, WidthsAroundWordBoundariesAreExact) {
  std::uint32_t seed = 1;
  for (std::uint32_t width :
       {1u, 2u, 61u, 62u, 63u, 64u, 65u, 66u, 126u, 127u, 128u, 129u, 130u, 191u}) {
    for (std::uint32_t height : {1u, 2u, 5u}) {
      for (int density : {40, 128, 220}) {
        auto noise = noise_volume(width, height, 3, seed++);
        BinaryVolume binary(width, height, 3);
        for (std::size_t i = 0; i < noise.samples.size(); ++i)
          binary.samples[i] = noise.samples[i] < density;
        const std::string label = std::to_string(width) + "x" + std::to_string(height) +
                                  " density " + std::to_string(density);
        const Mesh fast = extract(binary, 1);
        EngineOptions literal;
        literal.kind = EngineKind::literal;
        ASSERT_TRUE(test::meshes_identical(fast, extract(binary, 1, literal))) << label;
        const test::Topology t = test::analyse(fast);
        ASSERT_TRUE(t.closed_and_consistent()) << label << ": " << test::describe(t);
        const std::vector<Vertex> expected = test::expected_vertices(binary);
        const std::vector<Vertex> actual = test::sorted_positions(fast);
        ASSERT_EQ(actual.size(), expected.size()) << label;
        for (std::size_t i = 0; i < actual.size(); ++i)
          ASSERT_TRUE(test::same_position(actual[i], expected[i])) << label << " vertex " << i;
      }
    }
  }
}

TEST(EngineOutput, CountersAgreeWithTheEmittedMesh) {
  const auto volume = noise_volume(31, 29, 17, 5);
  EngineCounters counters;
  const Mesh mesh = extract(volume, 140, {}, &counters);
  std::uint64_t inner = 0;
  for (std::uint8_t sample : volume.samples) inner += sample >= 140;
  EXPECT_EQ(counters.inner_voxels, inner);
  EXPECT_EQ(counters.slices, 17u);
  EXPECT_EQ(counters.vertices, mesh.vertices.size());
  EXPECT_EQ(counters.polygons, mesh.polygons.size());
  std::uint64_t by_size[8] = {};
  for (const auto& polygon : mesh.polygons) ++by_size[polygon.size()];
  for (int size = 0; size < 8; ++size) EXPECT_EQ(counters.polygons_by_size[size], by_size[size]);
  EXPECT_EQ(mesh.forward_references, 0u);
}

TEST(EngineOutput, VerticesCarryTheirAxisAndTheSideOfTheInnerVoxel) {
  BinaryVolume volume(7, 5, 6);  // odd, asymmetric: an axis swap cannot go unnoticed
  volume.at(3, 1, 4) = 1;
  const Mesh mesh = extract(volume, 1);
  ASSERT_EQ(mesh.vertices.size(), 6u);
  for (const Vertex& v : mesh.vertices) {
    const float offset[3] = {v.x - 3, v.y - 1, v.z - 4};
    const int axis = static_cast<int>(v.axis);
    for (int a = 0; a < 3; ++a)
      EXPECT_FLOAT_EQ(std::fabs(offset[a]), a == axis ? 0.5f : 0.0f) << "axis " << axis;
    EXPECT_EQ(v.inner_is_lower, offset[axis] > 0);
  }
  ASSERT_EQ(mesh.polygons.size(), 8u);  // the voxel's eight octant triangles, nothing merged
  EXPECT_TRUE(test::analyse(mesh).closed_and_consistent());
  // An octahedron with half-diagonals 0.5: volume 4/3 * 0.5^3.
  EXPECT_NEAR(test::analyse(mesh).signed_volume, 1.0 / 6.0, 1e-9);
}

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

TEST(EngineWorkspace, PolygonGeometryAddsOneBatchOfPolygonsByValue) {
  EXPECT_EQ(sizeof(PolygonGeometry), 116u);  // as engine.h states
  const std::uint32_t sizes[][2] = {{1, 1}, {7, 5}, {64, 3}, {513, 300}};
  for (const auto& size : sizes)
    for (EngineKind kind : {EngineKind::fast, EngineKind::literal})
      for (std::uint32_t batch : {1u, 2u, 3u, 5u, 7u, 4096u}) {
        EngineOptions off;
        off.kind = kind;
        off.polygons_per_batch = batch;
        EngineOptions on = off;
        on.polygon_geometry = true;
        // Every buffer starts on kWorkspaceAlignment (8): odd batches of 116 bytes round up by 4.
        const std::size_t expected_extra = (batch * sizeof(PolygonGeometry) + 7) / 8 * 8;
        EXPECT_EQ(engine_workspace_bytes(size[0], size[1], on) -
                      engine_workspace_bytes(size[0], size[1], off),
                  expected_extra)
            << size[0] << "x" << size[1] << " batch " << batch;
      }
  // And init() asks for all of it.
  EngineOptions on;
  on.polygon_geometry = true;
  on.vertices_per_batch = 4;
  on.polygons_per_batch = 3;
  const std::size_t bound = engine_workspace_bytes(7, 5, on);
  Workspace workspace(bound);
  CountingSink sink;
  Engine engine;
  for (std::size_t bytes = 0; bytes < bound; ++bytes)
    ASSERT_EQ(engine.init(workspace.data(), bytes, 7, 5, 1, on, &sink), Status::workspace_too_small)
        << bytes << " of " << bound;
  EXPECT_EQ(engine.init(workspace.data(), bound, 7, 5, 1, on, &sink), Status::ok);
}

}  // namespace
}  // namespace mvox
