// --decimate / --max-error (src/postprocess/layer_decimation.h): simplified as the layers
// stream, the surface stays closed and manifold (every directed edge once, its reverse once),
// keeps about the share of triangles asked for, uses only the engine's vertices, each sent
// before a triangle uses it; the triangles by value are the indexed ones; what is held does not
// grow with the number of slices; and folds left by the simplifier are cancelled in pairs.
#include "postprocess/layer_decimation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <set>
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

struct Decimated {
  Mesh mesh;
  std::vector<PolygonGeometry> geometry;
  std::uint64_t triangles_in = 0;
  std::size_t most_triangles_held = 0;
  std::size_t most_vertices_held = 0;
  std::uint64_t retried_passes = 0;
};

Decimated decimate(SliceSource& source, double threshold, const DecimationOptions& options,
                   bool geometry = false) {
  test::MeshCapture capture;
  LayerDecimation decimation(capture, options, geometry);
  test::stream_into(source, threshold, decimation);
  EXPECT_EQ(decimation.finish(), Status::ok);
  EXPECT_EQ(decimation.triangles_out(), capture.mesh.polygons.size());
  EXPECT_EQ(decimation.vertices_out(), capture.mesh.vertices.size());
  return {capture.mesh,
          capture.geometry,
          decimation.triangles_in(),
          decimation.most_triangles_held(),
          decimation.most_vertices_held(),
          decimation.retried_passes()};
}

DecimationOptions keeping(double ratio) {
  DecimationOptions options;
  options.ratio = ratio;
  return options;
}

// Every directed edge once and its reverse once, nothing degenerate, every vertex used.
void expect_closed_manifold(const Mesh& mesh, const char* what) {
  const test::Topology topology = test::analyse(mesh);
  EXPECT_TRUE(topology.closed_and_consistent()) << what << ": " << test::describe(topology);
}

TEST(LayerDecimation, PhantomsStayClosedAndManifoldAtTheRatioAsked) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  const sim::Sphere sphere(sim::Grid{60, 56, 70}, {29.6, 27.3, 34.8}, 24.2);
  const sim::RandomBlobs blobs(sim::Grid{64, 60, 72}, 3, 24);
  for (const sim::Phantom* phantom :
       {static_cast<const sim::Phantom*>(&sphere), static_cast<const sim::Phantom*>(&blobs)}) {
    for (const double ratio : {0.5, 0.1}) {
      sim::SimulatedScanner scanner(*phantom, sim::default_scan_options(SampleType::u8));
      const Decimated result = decimate(scanner, 128, keeping(ratio));
      ASSERT_GT(result.triangles_in, 5000u);
      const double kept = double(result.mesh.polygons.size()) / double(result.triangles_in);
      EXPECT_LT(kept, ratio * 1.3) << phantom->name() << " " << ratio;
      EXPECT_GT(kept, ratio * 0.5) << phantom->name() << " " << ratio;
      EXPECT_EQ(result.mesh.forward_references, 0u);
      expect_closed_manifold(result.mesh, phantom->name());
      // Only the engine's vertices: a simplification collapses onto existing ones.
      sim::SimulatedScanner again(*phantom, sim::default_scan_options(SampleType::u8));
      const Mesh plain = test::extract(again, 128);
      std::set<std::array<float, 3>> positions;
      for (const Vertex& v : plain.vertices) positions.insert({v.x, v.y, v.z});
      for (const Vertex& v : result.mesh.vertices) ASSERT_EQ(positions.count({v.x, v.y, v.z}), 1u);
    }
  }
}

TEST(LayerDecimation, NoiseStaysClosedAndManifoldEvenWhereTheSimplifierPinches) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  // Random voxels: sheets a voxel apart everywhere, where meshopt_simplify pinches two sheets
  // into one edge unless the pass is run again with those vertices frozen.
  std::uint64_t retried = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const auto volume = test::noise_volume(40, 36, 48, static_cast<std::uint32_t>(seed));
    std::vector<SliceView> slices;
    for (std::uint32_t z = 0; z < volume.depth; ++z) slices.push_back(test::slice_of(volume, z));
    class Slices : public SliceSource {
     public:
      Slices(const std::vector<SliceView>& slices, VolumeInfo info)
          : slices_(slices), info_(info) {}
      const VolumeInfo& info() const override { return info_; }
      bool next_slice(SliceView* slice) override {
        if (next_ == slices_.size()) return false;
        *slice = slices_[next_++];
        return true;
      }

     private:
      const std::vector<SliceView>& slices_;
      VolumeInfo info_;
      std::size_t next_ = 0;
    };
    VolumeInfo info;
    info.width = volume.width;
    info.height = volume.height;
    info.depth = volume.depth;
    Slices source(slices, info);
    const Decimated result = decimate(source, 200, keeping(0.3));
    expect_closed_manifold(result.mesh, "noise");
    retried += result.retried_passes;
  }
  std::printf("passes run again with frozen vertices: %llu\n",
              static_cast<unsigned long long>(retried));
}

TEST(LayerDecimation, AnErrorBoundAloneSimplifiesLessWhenTighter) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  const sim::Sphere sphere(sim::Grid{60, 56, 70}, {29.6, 27.3, 34.8}, 24.2);
  std::size_t loose = 0, tight = 0;
  for (const double error : {0.05, 1.0}) {
    DecimationOptions options;
    options.max_error_voxels = error;
    sim::SimulatedScanner scanner(sphere, sim::default_scan_options(SampleType::u8));
    const Decimated result = decimate(scanner, 128, options);
    expect_closed_manifold(result.mesh, "error bound");
    (error < 0.5 ? tight : loose) = result.mesh.polygons.size();
    EXPECT_LT(result.mesh.polygons.size(), result.triangles_in);
  }
  EXPECT_LT(loose, tight);
}

TEST(LayerDecimation, TrianglesByValueAreTheIndexedOnes) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  const sim::Sphere sphere(sim::Grid{40, 40, 40}, {19.6, 20.3, 19.8}, 15.2);
  sim::SimulatedScanner scanner(sphere, sim::default_scan_options(SampleType::u8));
  const Decimated result = decimate(scanner, 128, keeping(0.2), true);
  ASSERT_EQ(result.geometry.size(), result.mesh.polygons.size());
  for (std::size_t p = 0; p < result.geometry.size(); ++p)
    for (int k = 0; k < 3; ++k)
      ASSERT_TRUE(test::same_position(result.geometry[p].vertices[k],
                                      result.mesh.vertices[result.mesh.polygons[p][k]]));
}

// A long cylinder of the same cross-section: the same surface per slice at any depth. With a
// loose error bound the simplifier joins an old locked border vertex to the newest layer pass
// after pass (one long flat stretch): the vertices in between must still be let go.
class Cylinder : public sim::Phantom {
 public:
  explicit Cylinder(std::uint32_t depth) : depth_(depth) {}
  sim::Grid grid() const override { return {32, 32, depth_}; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t) const override {
    const double dx = x - 15.4, dy = y - 16.2;
    return dx * dx + dy * dy <= 11.3 * 11.3 ? 1.0f : 0.0f;
  }
  const char* name() const override { return "cylinder"; }

 private:
  std::uint32_t depth_;
};

TEST(LayerDecimation, WhatIsHeldDoesNotGrowWithTheSlices) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  DecimationOptions loose;
  loose.max_error_voxels = 3.0;
  for (const DecimationOptions& options : {keeping(0.2), loose}) {
    std::size_t triangles[2] = {}, vertices[2] = {};
    int k = 0;
    for (const std::uint32_t depth : {80u, 640u}) {
      const Cylinder cylinder(depth);
      sim::SimulatedScanner scanner(cylinder, sim::default_scan_options(SampleType::u8));
      const Decimated result = decimate(scanner, 128, options);
      expect_closed_manifold(result.mesh, "cylinder");
      triangles[k] = result.most_triangles_held;
      vertices[k++] = result.most_vertices_held;
    }
    EXPECT_GT(triangles[0], 0u);
    EXPECT_LE(triangles[1], triangles[0] + triangles[0] / 5) << options.max_error_voxels;
    EXPECT_LE(vertices[1], vertices[0] + vertices[0] / 5) << options.max_error_voxels;
  }
}

TEST(LayerDecimation, FoldsAreCancelledInPairs) {
  using Triangle = LayerDecimation::Triangle;
  std::vector<Triangle> triangles = {{{1, 2, 3}}, {{3, 2, 1}}, {{2, 3, 1}}, {{4, 5, 6}},
                                     {{5, 6, 4}}, {{7, 8, 9}}, {{9, 8, 7}}};
  cancel_folds(triangles);
  // 1 2 3 and 3 2 1 pair off (2 3 1 is 1 2 3 again: one of the two stays); 4 5 6 and 5 6 4
  // are one winding: both stay; 7 8 9 and 9 8 7 pair off.
  ASSERT_EQ(triangles.size(), 3u);
  std::multiset<std::array<std::uint64_t, 3>> left;
  for (const Triangle& t : triangles) left.insert({t.v[0], t.v[1], t.v[2]});
  EXPECT_EQ(left.count({4, 5, 6}) + left.count({5, 6, 4}), 2u);
  EXPECT_EQ(left.count({1, 2, 3}) + left.count({2, 3, 1}), 1u);
}

}  // namespace
}  // namespace mvox
