// The surface on phantoms from sim/: closed and consistently wound, the right topology, every
// vertex once at an inner/outer midpoint, literal = fast, streaming = whole-volume processing.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "phantom_factory.h"
#include "random_phantoms.h"
#include "shapes.h"
#include "simulated_scanner.h"
#include "whole_volume_reference.h"

namespace mvox {
namespace {

using test::analyse;
using test::describe;
using test::Mesh;

constexpr double kPi = 3.14159265358979323846;

// The phantom's voxels classified at density >= 0.5 (the binary phantoms are 0 or 1).
test::BinaryVolume binary_volume(const sim::Phantom& phantom, double density_threshold = 0.5) {
  const sim::Grid grid = phantom.grid();
  test::BinaryVolume volume(grid.width, grid.height, grid.depth);
  const std::vector<float> densities = sim::sample_volume(phantom);
  for (std::size_t i = 0; i < densities.size(); ++i)
    volume.samples[i] = densities[i] >= density_threshold;
  return volume;
}

// Streams the phantom through the simulated scanner (as a reader would feed the engine).
Mesh scan(const sim::Phantom& phantom, double density_threshold = 0.5, EngineOptions options = {},
          SampleType type = SampleType::u8) {
  const sim::ScanOptions scan_options = sim::default_scan_options(type);
  sim::SimulatedScanner scanner(phantom, scan_options);
  return test::extract(scanner, sim::sample_threshold(density_threshold, scan_options), options);
}

// Every vertex is the midpoint of an inner and an outer 6-adjacent voxel, once each, and every
// such pair has its vertex.
void expect_vertices_at_every_inner_outer_pair(const Mesh& mesh, const test::BinaryVolume& volume) {
  const std::vector<Vertex> expected = test::expected_vertices(volume);
  const std::vector<Vertex> actual = test::sorted_positions(mesh);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i)
    ASSERT_TRUE(test::same_position(actual[i], expected[i]))
        << "vertex " << i << " at (" << actual[i].x << "," << actual[i].y << "," << actual[i].z
        << "), expected (" << expected[i].x << "," << expected[i].y << "," << expected[i].z << ")";
}

void expect_literal_equals_fast(const sim::Phantom& phantom, double density_threshold = 0.5) {
  EngineOptions literal;
  literal.kind = EngineKind::literal;
  EXPECT_TRUE(test::meshes_identical(scan(phantom, density_threshold),
                                     scan(phantom, density_threshold, literal)));
}

TEST(PhantomSurface, SphereIsOneClosedSurfaceOfGenusZero) {
  const sim::Grid grid{40, 36, 32};
  const sim::Sphere sphere(grid, sim::grid_centre(grid), 13.2);
  const Mesh mesh = scan(sphere);
  const test::Topology t = analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_EQ(t.euler(), 2) << describe(t);
  EXPECT_EQ(t.components, 1u);
  // The polygons cut the voxel corners, so the enclosed volume is a little below the ball's.
  const double ball = 4.0 / 3.0 * kPi * std::pow(13.2, 3);
  EXPECT_GT(t.signed_volume, 0.9 * ball);
  EXPECT_LT(t.signed_volume, 1.05 * ball);
  expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(sphere));
  expect_literal_equals_fast(sphere);
}

TEST(PhantomSurface, TorusHasEulerCharacteristicZero) {
  const sim::Grid grid{48, 44, 20};
  const sim::Torus torus(grid, sim::grid_centre(grid), 13.0, 5.0);
  const Mesh mesh = scan(torus);
  const test::Topology t = analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_EQ(t.euler(), 0) << describe(t);
  EXPECT_EQ(t.components, 1u);
  EXPECT_GT(t.signed_volume, 0);
  expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(torus));
  expect_literal_equals_fast(torus);
}

TEST(PhantomSurface, HollowShellIsTwoSpheresWithEulerCharacteristicFour) {
  const sim::Grid grid{36, 36, 36};
  const sim::NestedShells shell(grid, sim::grid_centre(grid), {15.0, 9.5});
  const Mesh mesh = scan(shell);
  const test::Topology t = analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_EQ(t.euler(), 4) << describe(t);
  EXPECT_EQ(t.components, 2u);
  // The cavity's surface faces inwards, so it subtracts: the shell's volume remains.
  const double shell_volume = 4.0 / 3.0 * kPi * (std::pow(15.0, 3) - std::pow(9.5, 3));
  EXPECT_GT(t.signed_volume, 0.85 * shell_volume);
  EXPECT_LT(t.signed_volume, 1.1 * shell_volume);
  expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(shell));
  expect_literal_equals_fast(shell);
}

TEST(PhantomSurface, NestedShellsGiveOneSphereSurfacePerRadius) {
  const sim::Grid grid{44, 44, 44};
  const sim::NestedShells shells(grid, sim::grid_centre(grid), {20.0, 15.5, 11.0, 6.5, 3.0});
  const test::Topology t = analyse(scan(shells));
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_EQ(t.components, 5u);
  EXPECT_EQ(t.euler(), 10) << describe(t);
  expect_literal_equals_fast(shells);
}

TEST(PhantomSurface, OddAsymmetricGridKeepsTheAxesApart) {
  // 7x5x6 with a small ball off centre on every axis: an axis swap moves vertices off the oracle.
  const sim::Grid grid{7, 5, 6};
  const sim::Sphere sphere(grid, {4.2, 1.7, 3.1}, 1.6);
  const Mesh mesh = scan(sphere);
  const test::Topology t = analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_EQ(t.euler(), 2);
  expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(sphere));
  expect_literal_equals_fast(sphere);
}

TEST(PhantomSurface, SheppLoganHeadIsClosedAndBothEnginesAgree) {
  const auto head = sim::make_phantom("shepp-logan", {64, 64, 64}, 1);
  const double threshold = sim::default_density_threshold("shepp-logan");
  const Mesh mesh = scan(*head, threshold);
  const test::Topology t = analyse(mesh);
  EXPECT_TRUE(t.closed_and_consistent()) << describe(t);
  EXPECT_GE(t.components, 3u);  // the skull's two surfaces and at least one inner feature
  EXPECT_GT(t.signed_volume, 0);
  expect_literal_equals_fast(*head, threshold);
}

TEST(PhantomSurface, RandomBlobsAreClosedWithEvenEulerCharacteristic) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const sim::RandomBlobs blobs({48, 40, 36}, seed, 40);
    const Mesh mesh = scan(blobs);
    const test::Topology t = analyse(mesh);
    EXPECT_TRUE(t.closed_and_consistent()) << "seed " << seed << ": " << describe(t);
    EXPECT_EQ(t.euler() % 2, 0);
    EXPECT_LE(t.euler(), 2 * static_cast<std::int64_t>(t.components));
    expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(blobs));
    expect_literal_equals_fast(blobs);
  }
}

TEST(PhantomSurface, RandomVoxelsAtEveryDensityAreClosed) {
  // Noise is the hardest case: every cube configuration occurs, ambiguous faces everywhere.
  for (double p : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const sim::RandomVoxels random({33, 29, 23}, 7, p);
    const Mesh mesh = scan(random);
    const test::Topology t = analyse(mesh);
    EXPECT_TRUE(t.closed_and_consistent()) << "p " << p << ": " << describe(t);
    EXPECT_EQ(t.euler() % 2, 0);
    expect_vertices_at_every_inner_outer_pair(mesh, binary_volume(random));
    expect_literal_equals_fast(random);
  }
}

TEST(PhantomSurface, StreamingEqualsWholeVolumeProcessing) {
  const sim::RandomVoxels random({19, 17, 13}, 3, 0.45);
  const sim::RandomBlobs blobs({30, 26, 22}, 5, 20);
  const sim::Torus torus({30, 28, 12}, {14.5, 13.5, 5.5}, 8.0, 3.5);
  for (const sim::Phantom* phantom :
       {static_cast<const sim::Phantom*>(&random), static_cast<const sim::Phantom*>(&blobs),
        static_cast<const sim::Phantom*>(&torus)}) {
    const Mesh streamed = scan(*phantom);
    const Mesh whole = test::whole_volume_reference(binary_volume(*phantom));
    EXPECT_EQ(streamed.vertices.size(), whole.vertices.size()) << phantom->name();
    EXPECT_EQ(test::canonical_form(streamed), test::canonical_form(whole)) << phantom->name();
  }
}

TEST(PhantomSurface, EverySampleTypeGivesTheSameSurface) {
  const sim::RandomBlobs blobs({30, 26, 22}, 9, 20);
  const Mesh reference = scan(blobs);
  for (SampleType type : {SampleType::u16, SampleType::i16, SampleType::f32})
    EXPECT_TRUE(test::meshes_identical(reference, scan(blobs, 0.5, {}, type)))
        << sample_type_name(type);
}

TEST(PhantomSurface, PaperTable1OpensHolesOnNoiseWhereTheDefaultHasNone) {
  const sim::RandomVoxels random({24, 22, 20}, 11, 0.6);
  EngineOptions paper;
  paper.rule = SurfaceRule::paper_table1;
  const test::Topology merge_rules = analyse(scan(random));
  const test::Topology table1 = analyse(scan(random, 0.5, paper));
  EXPECT_EQ(merge_rules.open_edges, 0u);
  EXPECT_GT(table1.open_edges, 0u) << describe(table1);
  paper.kind = EngineKind::literal;
  EXPECT_EQ(analyse(scan(random, 0.5, paper)).open_edges, table1.open_edges);
}

}  // namespace
}  // namespace mvox
