// Marching voxels with interpolated vertices (EngineOptions::interpolate, --interpolate): each
// vertex moves along its voxel edge to where the linearly interpolated samples cross the
// threshold, and nothing else changes: the same polygons, indices and counts (so the surface
// stays closed), midpoints kept at the volume's border, every engine kind and batch size alike,
// and the polygons sent by value (for the picture) at the moved positions. (On a distance field
// they lie on the sphere as marching cubes' do: marching_cubes_test.cpp checks both.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "mvox/engine.h"
#include "shapes.h"
#include "simulated_scanner.h"

namespace mvox {
namespace {

using test::Mesh;
using test::Volume;

EngineOptions interpolated(EngineKind kind = EngineKind::fast) {
  EngineOptions options;
  options.kind = kind;
  options.interpolate = true;
  return options;
}

// A float volume of smooth random values: crossings anywhere along the edges.
Volume<float> wavy_volume(std::uint32_t w, std::uint32_t h, std::uint32_t d) {
  Volume<float> volume(w, h, d);
  for (std::uint32_t z = 0; z < d; ++z)
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x)
        volume.at(x, y, z) = static_cast<float>(std::sin(0.9 * x + 0.3) * std::cos(0.7 * y - 0.2) +
                                                std::sin(0.55 * z + 0.4 * x) +
                                                0.1 * ((x * 7 + y * 13 + z * 5) % 11));
  return volume;
}

TEST(InterpolatedVoxels, SamePolygonsEachVertexMovedAlongItsOwnEdgeToTheCrossing) {
  const Volume<float> volume = wavy_volume(23, 17, 13);
  const double threshold = 0.6;
  EngineCounters plain_counters, moved_counters;
  const Mesh plain = test::extract(volume, threshold, {}, &plain_counters);
  const Mesh moved = test::extract(volume, threshold, interpolated(), &moved_counters);
  ASSERT_GT(plain.polygons.size(), 500u);
  EXPECT_EQ(moved.polygons, plain.polygons);
  ASSERT_EQ(moved.vertices.size(), plain.vertices.size());
  EXPECT_EQ(moved_counters.polygons, plain_counters.polygons);
  std::size_t inside = 0, border = 0;
  for (std::size_t i = 0; i < plain.vertices.size(); ++i) {
    const Vertex &m = plain.vertices[i], &v = moved.vertices[i];
    ASSERT_EQ(v.axis, m.axis);
    ASSERT_EQ(v.inner_is_lower, m.inner_is_lower);
    // Only the coordinate along its edge changes, and it stays on the segment between the
    // edge's two voxels.
    for (const Axis other : {Axis::x, Axis::y, Axis::z}) {
      if (other == m.axis) continue;
      const float a = other == Axis::x ? m.x : other == Axis::y ? m.y : m.z;
      const float b = other == Axis::x ? v.x : other == Axis::y ? v.y : v.z;
      ASSERT_EQ(a, b) << "vertex " << i;
    }
    const float lower = along_axis(m) - 0.5f;
    const std::uint32_t size = m.axis == Axis::x   ? volume.width
                               : m.axis == Axis::y ? volume.height
                                                   : volume.depth;
    if (lower < 0.0f || lower + 1.0f >= static_cast<float>(size)) {
      EXPECT_EQ(along_axis(v), along_axis(m))
          << "vertex " << i << " on the border keeps its midpoint";
      ++border;
      continue;
    }
    ASSERT_GE(along_axis(v), lower) << "vertex " << i;
    ASSERT_LE(along_axis(v), lower + 1.0f) << "vertex " << i;
    // There the samples, interpolated linearly between the two voxels, equal the threshold.
    const auto x = static_cast<std::uint32_t>(m.axis == Axis::x ? lower : m.x);
    const auto y = static_cast<std::uint32_t>(m.axis == Axis::y ? lower : m.y);
    const auto z = static_cast<std::uint32_t>(m.axis == Axis::z ? lower : m.z);
    const float a = volume.at(x, y, z);
    const float b =
        volume.at(x + (m.axis == Axis::x), y + (m.axis == Axis::y), z + (m.axis == Axis::z));
    const float t = along_axis(v) - lower;
    // 0.01 voxel short of either voxel centre at most (engine.h), else where they cross.
    const float crossing = (static_cast<float>(threshold) - a) / (b - a);
    if (crossing > 0.01f && crossing < 0.99f)
      EXPECT_NEAR(a + t * (b - a), threshold, 1e-4) << "vertex " << i;
    else
      EXPECT_NEAR(t, crossing < 0.5f ? 0.01f : 0.99f, 1e-5) << "vertex " << i;
    ++inside;
  }
  EXPECT_GT(inside, 500u);
  EXPECT_GT(border, 10u);
}

TEST(InterpolatedVoxels, TheSurfaceStaysClosedAndManifold) {
  const Volume<float> volume = wavy_volume(19, 15, 11);
  const test::Topology topology = test::analyse(test::extract(volume, 0.6, interpolated()));
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_GT(topology.signed_volume, 0.0) << "wound outward";
}

// The simulated scanner's sphere with partial-volume edges (a one-voxel ramp across the boundary,
// as a real scan records it), u8 samples: the mean distance of the vertices to the true sphere
// is what a printed or measured mesh shows. Midpoints are about a sixth of a voxel off on
// average (the terraces); interpolated vertices a few hundredths.
TEST(InterpolatedVoxels, OnAScannedSphereTheMeanDistanceDropsTenfold) {
  const sim::Grid grid{64, 64, 64};
  const sim::Point3 centre{31.7, 32.2, 31.9};
  const double radius = 23.3;
  const sim::Sphere sphere(grid, centre, radius);
  sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
  scan.partial_volume = true;
  auto mean_distance = [&](const EngineOptions& options) {
    sim::SimulatedScanner scanner(sphere, scan);
    const Mesh mesh = test::extract(scanner, sim::sample_threshold(0.5, scan), options);
    double sum = 0;
    for (const Vertex& v : mesh.vertices)
      sum += std::abs(std::sqrt((v.x - centre.x) * (v.x - centre.x) +
                                (v.y - centre.y) * (v.y - centre.y) +
                                (v.z - centre.z) * (v.z - centre.z)) -
                      radius);
    return sum / static_cast<double>(mesh.vertices.size());
  };
  const double midpoints = mean_distance({});
  const double moved = mean_distance(interpolated());
  EXPECT_GT(midpoints, 0.12);
  EXPECT_LT(moved, 0.03);
  std::printf("mean distance to the sphere: midpoints %.4f, interpolated %.4f voxels\n", midpoints,
              moved);
}

TEST(InterpolatedVoxels, EveryKindAndBatchSizeGivesTheSameMesh) {
  const Volume<float> volume = wavy_volume(70, 9, 7);  // rows over a 64-bit word
  const Mesh fast = test::extract(volume, 0.6, interpolated());
  EXPECT_TRUE(
      test::meshes_identical(test::extract(volume, 0.6, interpolated(EngineKind::literal)), fast));
  EngineOptions tiny = interpolated();
  tiny.vertices_per_batch = 1;
  tiny.polygons_per_batch = 2;
  tiny.polygon_geometry = true;
  EXPECT_TRUE(test::meshes_identical(test::extract(volume, 0.6, tiny), fast));
}

// What a renderer is sent: each polygon by value, which must be the indexed vertices as moved.
class GeometryCapture : public PolygonSink {
 public:
  Status consume_vertices(const Vertex* vertices, std::size_t count) override {
    this->vertices.insert(this->vertices.end(), vertices, vertices + count);
    return Status::ok;
  }
  Status consume_polygons(const Polygon* polygons, std::size_t count) override {
    this->polygons.insert(this->polygons.end(), polygons, polygons + count);
    return Status::ok;
  }
  Status consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t count) override {
    geometry.insert(geometry.end(), polygons, polygons + count);
    return Status::ok;
  }
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  std::vector<PolygonGeometry> geometry;
};

TEST(InterpolatedVoxels, PolygonsSentByValueUseTheMovedVertices) {
  for (const EngineKind kind : {EngineKind::fast, EngineKind::literal}) {
    const Volume<float> volume = wavy_volume(21, 13, 9);
    EngineOptions options = interpolated(kind);
    options.polygon_geometry = true;
    GeometryCapture capture;
    test::Workspace workspace(engine_workspace_bytes(volume.width, volume.height, options));
    Engine engine;
    ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), volume.width, volume.height, 0.6,
                          options, &capture),
              Status::ok);
    for (std::uint32_t z = 0; z < volume.depth; ++z) {
      SliceView slice;
      slice.samples = &volume.samples[std::size_t{z} * volume.width * volume.height];
      slice.width = volume.width;
      slice.height = volume.height;
      slice.row_stride_bytes = volume.width * sizeof(float);
      slice.type = SampleType::f32;
      ASSERT_EQ(engine.push_slice(slice), Status::ok);
    }
    ASSERT_EQ(engine.finish(), Status::ok);
    ASSERT_EQ(capture.geometry.size(), capture.polygons.size());
    std::size_t moved = 0;
    for (std::size_t p = 0; p < capture.polygons.size(); ++p) {
      const Polygon& polygon = capture.polygons[p];
      const PolygonGeometry& by_value = capture.geometry[p];
      ASSERT_EQ(by_value.vertex_count, polygon.vertex_count);
      for (int k = 0; k < polygon.vertex_count; ++k) {
        const Vertex& indexed = capture.vertices[polygon.vertices[k]];
        ASSERT_TRUE(test::same_position(by_value.vertices[k], indexed))
            << "polygon " << p << " corner " << k;
        moved += std::fmod(along_axis(indexed), 1.0f) != 0.5f;
      }
    }
    EXPECT_GT(moved, 100u) << "the case must move vertices off their midpoints";
  }
}

// Samples equal to the threshold put the crossing on a voxel centre: the vertex stops 0.01 voxel
// short of it, so that it keeps one fractional coordinate and its polygon can be split into
// triangles (none lying in a cube face).
TEST(InterpolatedVoxels, ASampleAtTheThresholdKeepsTheVertexOffTheVoxelCentre) {
  Volume<std::uint8_t> volume(9, 8, 7);
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    for (std::uint32_t y = 0; y < volume.height; ++y)
      for (std::uint32_t x = 0; x < volume.width; ++x)
        volume.at(x, y, z) = (x * 7 + y * 5 + z * 3) % 5 == 0 ? 100 : (x + y + z) % 3 ? 0 : 255;
  const Mesh moved = test::extract(volume, 100.0, interpolated());
  std::size_t at_margin = 0;
  for (const Vertex& v : moved.vertices) {
    int whole = 0;
    for (const float c : {v.x, v.y, v.z}) whole += c == std::floor(c);
    ASSERT_EQ(whole, 2) << v.x << "," << v.y << "," << v.z;
    const float fraction = along_axis(v) - std::floor(along_axis(v));
    at_margin += std::fabs(fraction - 0.01f) < 1e-4f || std::fabs(fraction - 0.99f) < 1e-4f;
  }
  EXPECT_GT(at_margin, 10u);
}

TEST(InterpolatedVoxels, WorkspaceGrowsByTwoSlicesOfSamples) {
  const std::size_t plain = engine_workspace_bytes(256, 256, EngineOptions());
  const std::size_t moved = engine_workspace_bytes(256, 256, interpolated());
  EXPECT_GE(moved - plain, std::size_t{8} * 256 * 256);
  EXPECT_LT(moved - plain, std::size_t{8} * 256 * 256 + 2 * kWorkspaceAlignment);
}

}  // namespace
}  // namespace mvox
