// --smooth N (src/postprocess/edge_smoothing.h): the smoothing done as the layers stream equals
// the same iterations done on the whole mesh at once, number for number; every vertex stays on
// its own voxel edge segment, the polygons are the engine's and the surface stays closed; a
// binary sphere's face normals come within a few degrees of the true ones; the polygons sent by
// value are at the smoothed positions; and the layers held do not grow with the slice count.
#include "postprocess/edge_smoothing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mesh_capture.h"
#include "mesh_topology.h"
#include "mvox/engine.h"
#include "mvox/stream_volume.h"
#include "random_phantoms.h"
#include "shapes.h"
#include "simulated_scanner.h"

namespace mvox {
namespace {

using test::Mesh;

struct Smoothed {
  Mesh mesh;
  std::vector<PolygonGeometry> geometry;
  std::size_t most_layers_held = 0;
};

// The engine's mesh of `source`, through EdgeSmoothing as the pipeline runs it.
Smoothed smooth_streamed(SliceSource& source, double threshold, std::uint32_t iterations,
                         bool geometry = false) {
  test::MeshCapture capture;
  EdgeSmoothing smoothing(capture, source.info(), iterations, geometry);
  auto layer_done = [&](std::uint32_t) { EXPECT_EQ(smoothing.end_layer(), Status::ok); };
  test::stream_into(source, threshold, smoothing, {}, SliceProgress::of(layer_done));
  EXPECT_EQ(smoothing.finish(), Status::ok);
  return {capture.mesh, capture.geometry, smoothing.most_layers_held()};
}

// The same iterations on the whole mesh at once: the scheme of edge_smoothing.h written
// plainly, with the same arithmetic (positions kept as floats between iterations, each
// vertex's neighbours and faces taken in the engine's polygon order).
Mesh smooth_whole(Mesh mesh, const VolumeInfo& volume, std::uint32_t iterations) {
  const std::uint32_t size[3] = {volume.width, volume.height, volume.depth};
  const std::size_t count = mesh.vertices.size();
  for (std::uint32_t k = 0; k < iterations; ++k) {
    std::vector<double> sums(3 * count, 0.0), normals(3 * count, 0.0);
    std::vector<std::uint32_t> counts(count, 0);
    for (const auto& polygon : mesh.polygons) {
      const int n = static_cast<int>(polygon.size());
      double p[kMaxPolygonVertices][3];
      for (int c = 0; c < n; ++c) {
        const Vertex& v = mesh.vertices[polygon[c]];
        p[c][0] = v.x;
        p[c][1] = v.y;
        p[c][2] = v.z;
      }
      double area[3] = {0, 0, 0};
      for (int c = 0; c < n; ++c) {
        const double* a = p[c];
        const double* b = p[(c + 1) % n];
        area[0] += 0.5 * (a[1] * b[2] - a[2] * b[1]);
        area[1] += 0.5 * (a[2] * b[0] - a[0] * b[2]);
        area[2] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
      }
      for (int c = 0; c < n; ++c) {
        const std::uint32_t i = polygon[c];
        for (int d = 0; d < 3; ++d) {
          sums[3 * i + d] += p[(c + n - 1) % n][d] + p[(c + 1) % n][d];
          normals[3 * i + d] += area[d];
        }
        counts[i] += 2;
      }
    }
    std::vector<Vertex> next = mesh.vertices;
    for (std::size_t i = 0; i < count; ++i) {
      const Vertex& v = mesh.vertices[i];
      const int axis = static_cast<int>(v.axis);
      const float lower =
          v.inner_is_lower ? std::floor(along_axis(v)) : std::ceil(along_axis(v)) - 1.0f;
      if (lower < 0.0f || lower + 1.0f >= static_cast<float>(size[axis]) || counts[i] == 0)
        continue;
      const double* nv = &normals[3 * i];
      const double length = std::sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
      if (!(length > 0.0)) continue;
      const double p[3] = {v.x, v.y, v.z};
      double across = 0.0;
      for (int d = 0; d < 3; ++d) across += nv[d] / length * (sums[3 * i + d] / counts[i] - p[d]);
      double axis_normal = nv[axis] / length;
      if (std::fabs(axis_normal) < EdgeSmoothing::kMinAxisNormal)
        axis_normal = std::copysign(EdgeSmoothing::kMinAxisNormal, axis_normal);
      const double moved = p[axis] + EdgeSmoothing::kStep * across / axis_normal;
      along_axis(next[i]) =
          static_cast<float>(std::clamp(moved, double{lower + EdgeSmoothing::kMargin},
                                        double{lower + 1.0f - EdgeSmoothing::kMargin}));
    }
    mesh.vertices = next;
  }
  return mesh;
}

// Area-weighted mean angle, in degrees, between the faces' normals and the radial direction.
double normal_error_degrees(const Mesh& mesh, const sim::Point3& centre) {
  double weighted = 0, total = 0;
  for (const auto& polygon : mesh.polygons) {
    double area[3] = {0, 0, 0}, mid[3] = {0, 0, 0};
    const std::size_t n = polygon.size();
    for (std::size_t c = 0; c < n; ++c) {
      const Vertex& a = mesh.vertices[polygon[c]];
      const Vertex& b = mesh.vertices[polygon[(c + 1) % n]];
      area[0] += 0.5 * (double{a.y} * b.z - double{a.z} * b.y);
      area[1] += 0.5 * (double{a.z} * b.x - double{a.x} * b.z);
      area[2] += 0.5 * (double{a.x} * b.y - double{a.y} * b.x);
      mid[0] += a.x / double(n);
      mid[1] += a.y / double(n);
      mid[2] += a.z / double(n);
    }
    const double length = std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
    const double r[3] = {mid[0] - centre.x, mid[1] - centre.y, mid[2] - centre.z};
    const double r_length = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (length == 0 || r_length == 0) continue;
    const double cosine = (area[0] * r[0] + area[1] * r[1] + area[2] * r[2]) / length / r_length;
    weighted += length * std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI;
    total += length;
  }
  return weighted / total;
}

struct BinarySphere {
  sim::Grid grid{48, 44, 40};
  sim::Point3 centre{23.6, 21.9, 19.7};
  double radius = 16.3;
  sim::Sphere sphere{grid, centre, radius};
};

TEST(EdgeSmoothing, StreamedEqualsTheWholeMeshSmoothedAtOnce) {
  for (const std::uint32_t iterations : {1u, 2u, 5u}) {
    const sim::RandomBlobs blobs(sim::Grid{37, 29, 23}, 11, 12);
    sim::SimulatedScanner scanner(blobs, sim::default_scan_options(SampleType::u8));
    const Smoothed streamed = smooth_streamed(scanner, 128, iterations);
    sim::SimulatedScanner again(blobs, sim::default_scan_options(SampleType::u8));
    const Mesh plain = test::extract(again, 128);
    ASSERT_GT(plain.polygons.size(), 500u);
    const Mesh whole = smooth_whole(plain, again.info(), iterations);
    EXPECT_EQ(streamed.mesh.polygons, plain.polygons) << iterations;
    EXPECT_EQ(streamed.mesh.forward_references, 0u);
    ASSERT_EQ(streamed.mesh.vertices.size(), whole.vertices.size());
    std::size_t moved = 0;
    for (std::size_t i = 0; i < whole.vertices.size(); ++i) {
      ASSERT_TRUE(test::same_position(streamed.mesh.vertices[i], whole.vertices[i]))
          << "vertex " << i << " after " << iterations << " iterations";
      moved += !test::same_position(whole.vertices[i], plain.vertices[i]);
    }
    EXPECT_GT(moved, whole.vertices.size() / 2) << iterations;
  }
}

TEST(EdgeSmoothing, VerticesStayOnTheirEdgesAndTheSurfaceStaysClosed) {
  const sim::RandomBlobs blobs(sim::Grid{41, 33, 27}, 5, 12);
  sim::SimulatedScanner scanner(blobs, sim::default_scan_options(SampleType::u8));
  const Smoothed smoothed = smooth_streamed(scanner, 100, 10);
  sim::SimulatedScanner again(blobs, sim::default_scan_options(SampleType::u8));
  const Mesh plain = test::extract(again, 100);
  ASSERT_EQ(smoothed.mesh.vertices.size(), plain.vertices.size());
  const std::uint32_t size[3] = {41, 33, 27};
  for (std::size_t i = 0; i < plain.vertices.size(); ++i) {
    const Vertex &before = plain.vertices[i], &after = smoothed.mesh.vertices[i];
    const int axis = static_cast<int>(before.axis);
    for (int d = 0; d < 3; ++d)
      if (d != axis) ASSERT_EQ((&after.x)[d], (&before.x)[d]) << "vertex " << i;
    const float lower = along_axis(before) - 0.5f;
    if (lower < 0 || lower + 1 >= size[axis]) {
      EXPECT_EQ(along_axis(after), along_axis(before)) << "vertex " << i << " on the border stays";
      continue;
    }
    ASSERT_GE(along_axis(after), lower + EdgeSmoothing::kMargin * 0.999f) << "vertex " << i;
    ASSERT_LE(along_axis(after), lower + 1 - EdgeSmoothing::kMargin * 0.999f) << "vertex " << i;
  }
  const test::Topology topology = test::analyse(smoothed.mesh);
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_GT(topology.signed_volume, 0.0);
}

TEST(EdgeSmoothing, ABinarySpheresFaceNormalsComeNearTheTrueOnes) {
  const BinarySphere shape;
  sim::SimulatedScanner scanner(shape.sphere, sim::default_scan_options(SampleType::u8));
  const double before = normal_error_degrees(test::extract(scanner, 128), shape.centre);
  sim::SimulatedScanner again(shape.sphere, sim::default_scan_options(SampleType::u8));
  const double after = normal_error_degrees(smooth_streamed(again, 128, 10).mesh, shape.centre);
  std::printf("binary sphere, face normals vs radial: %.2f deg, smoothed 10 times %.2f deg\n",
              before, after);
  EXPECT_GT(before, 12.0);
  EXPECT_LT(after, 4.0);
}

TEST(EdgeSmoothing, PolygonsByValueAreAtTheSmoothedPositions) {
  const BinarySphere shape;
  sim::SimulatedScanner scanner(shape.sphere, sim::default_scan_options(SampleType::u8));
  const Smoothed smoothed = smooth_streamed(scanner, 128, 4, true);
  ASSERT_EQ(smoothed.geometry.size(), smoothed.mesh.polygons.size());
  for (std::size_t p = 0; p < smoothed.geometry.size(); ++p) {
    const auto& polygon = smoothed.mesh.polygons[p];
    ASSERT_EQ(smoothed.geometry[p].vertex_count, polygon.size());
    for (std::size_t k = 0; k < polygon.size(); ++k)
      ASSERT_TRUE(
          test::same_position(smoothed.geometry[p].vertices[k], smoothed.mesh.vertices[polygon[k]]))
          << "polygon " << p << " corner " << k;
  }
}

TEST(EdgeSmoothing, TheLayersHeldDoNotGrowWithTheSlices) {
  for (const std::uint32_t depth : {30u, 240u}) {
    const sim::Sphere sphere(sim::Grid{24, 24, depth}, {11.5, 12.2, depth / 2.0}, 10.0);
    sim::SimulatedScanner scanner(sphere, sim::default_scan_options(SampleType::u8));
    EXPECT_EQ(smooth_streamed(scanner, 128, 6).most_layers_held, 6u + 3) << depth;
  }
}

}  // namespace
}  // namespace mvox
