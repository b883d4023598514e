// The engine's output (mvox/engine.h): sample types and thresholds, batch sizes and row strides
// that must not change it, widths around the 64-bit words of a row, the counters, and what each
// vertex carries.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "mvox/engine.h"

namespace mvox {
namespace {

using test::BinaryVolume;
using test::extract;
using test::Mesh;
using test::noise_volume;

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

// Sinks may load all seven index slots of a polygon, whatever its count (the host's polygon scan
// and binary PLY's records do): every path writes each slot, those past the count too (0, or an
// index of the cube). The workspace here starts filled with a pattern no index of this volume
// takes, as an uninitialised one may hold anything.
TEST(EngineOutput, EveryIndexSlotOfEveryPolygonIsWritten) {
  const auto volume = noise_volume(37, 23, 9, 8);
  constexpr std::uint32_t kPattern = 0xa5a5a5a5;
  struct SlotCheck final : PolygonSink {
    Status consume_vertices(const Vertex*, std::size_t) override { return Status::ok; }
    Status consume_polygons(const Polygon* polygons, std::size_t count) override {
      for (std::size_t p = 0; p < count; ++p)
        for (std::uint32_t slot : polygons[p].vertices) unwritten += slot == kPattern;
      this->polygons += count;
      return Status::ok;
    }
    Status consume_polygon_geometry(const PolygonGeometry*, std::size_t) override {
      return Status::ok;
    }
    std::uint64_t polygons = 0, unwritten = 0;
  };
  EngineOptions fast, literal, cubes, geometry;
  literal.kind = EngineKind::literal;
  cubes.method = SurfaceMethod::cubes;
  geometry.polygon_geometry = true;
  for (const EngineOptions& options : {fast, literal, cubes, geometry}) {
    SCOPED_TRACE(std::string(options.kind == EngineKind::literal ? "literal" : "fast") +
                 (options.method == SurfaceMethod::cubes ? " cubes" : "") +
                 (options.polygon_geometry ? " geometry" : ""));
    const std::size_t bytes = engine_workspace_bytes(volume.width, volume.height, options);
    test::Workspace workspace(bytes);
    std::memset(workspace.data(), kPattern & 0xff, bytes);
    SlotCheck sink;
    Engine engine;
    ASSERT_EQ(
        engine.init(workspace.data(), bytes, volume.width, volume.height, 128, options, &sink),
        Status::ok);
    for (std::uint32_t z = 0; z < volume.depth; ++z) {
      const SliceView slice{volume.samples.data() + std::size_t{z} * volume.width * volume.height,
                            volume.width, volume.height, volume.width, SampleType::u8};
      ASSERT_EQ(engine.push_slice(slice), Status::ok);
    }
    ASSERT_EQ(engine.finish(), Status::ok);
    EXPECT_GT(sink.polygons, 1000u);
    EXPECT_EQ(sink.unwritten, 0u);
  }
}

// The fast path counts polygons by size in one register's 16-bit lanes, spilled when a batch is
// full, when a layer ends, and, in batches larger than a lane holds, between: a layer of this
// noise has about 200,000 polygons, more than 65,535 of one size between two full batches of
// 70,000 or 2^20. Every batch size gives the counts of the polygons emitted.
TEST(EngineOutput, CountsBySizeHoldForEveryBatchSize) {
  const auto volume = noise_volume(400, 400, 3, 9);
  for (const std::uint32_t batch : {1u, 7u, 4096u, 70000u, 1u << 20}) {
    EngineOptions options;
    options.polygons_per_batch = batch;
    EngineCounters counters;
    const Mesh mesh = extract(volume, 128, options, &counters);
    std::uint64_t by_size[8] = {};
    for (const auto& polygon : mesh.polygons) ++by_size[polygon.size()];
    ASSERT_GT(by_size[4], 2u * 65535u) << "too few quads to fill a lane";
    for (int size = 0; size < 8; ++size)
      EXPECT_EQ(counters.polygons_by_size[size], by_size[size])
          << "size " << size << ", batch " << batch;
    EXPECT_EQ(counters.polygons, mesh.polygons.size());
  }
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

}  // namespace
}  // namespace mvox
