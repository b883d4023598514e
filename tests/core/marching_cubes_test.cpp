// Classic marching cubes (--method cubes): its table, its vertices, the holes it leaves, and the
// cross-check with marching voxels that needs no external tool.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cube.h"
#include "cube_merge.h"
#include "marching_cubes_table.h"
#include "mesh_capture.h"
#include "mesh_topology.h"
#include "mvox/engine.h"
#include "phantom_factory.h"
#include "random_phantoms.h"

namespace mvox {
namespace {

using test::Mesh;
using test::Volume;

bool edge_is_crossed(unsigned config, int e) {
  return (config >> cube::edge_low_corner(e) & 1) != (config >> cube::edge_high_corner(e) & 1);
}

bool has_ambiguous_face(unsigned config) {
  for (int f = 0; f < cube::kFaces; ++f)
    if (cube::face_is_ambiguous(config, f)) return true;
  return false;
}

// ---------------------------------------------------------------------------------------------
// The table.

TEST(MarchingCubesTable, EveryConfigurationUsesExactlyItsCrossedEdges) {
  const MarchingCubesTable& table = marching_cubes_table();
  for (unsigned config = 0; config < 256; ++config) {
    const MarchingCubesCase& c = table.cases[config];
    std::set<int> used;
    for (int i = 0; i < 3 * c.triangle_count; ++i) used.insert(c.edges[i]);
    for (int e = 0; e < cube::kEdges; ++e)
      EXPECT_EQ(used.count(e) == 1, edge_is_crossed(config, e))
          << "configuration " << config << ", edge " << e;
    for (int t = 0; t < c.triangle_count; ++t) {
      const std::uint8_t* tri = c.edges + 3 * t;
      EXPECT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2])
          << "configuration " << config << ", triangle " << t;
    }
  }
}

// Inside one cube the triangles' shared sides cancel, and what remains are closed loops whose
// every segment lies on a cube face: how the surface continues into the neighbouring cubes.
TEST(MarchingCubesTable, TrianglesOfACubeCloseIntoLoopsOnItsFaces) {
  const MarchingCubesTable& table = marching_cubes_table();
  for (unsigned config = 1; config < 255; ++config) {
    const MarchingCubesCase& c = table.cases[config];
    std::multiset<std::pair<int, int>> sides;
    for (int t = 0; t < c.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) sides.insert({c.edges[3 * t + k], c.edges[3 * t + (k + 1) % 3]});
    std::map<int, int> out_degree, in_degree;
    for (const auto& [from, to] : sides) {
      if (sides.count({to, from}) > 0) continue;  // a side shared by two triangles
      EXPECT_EQ(sides.count({from, to}), 1u) << "configuration " << config << ": repeated side";
      EXPECT_GE(cube::shared_face(from, to), 0) << "configuration " << config << ": boundary "
                                                << from << "->" << to << " crosses the cube";
      ++out_degree[from];
      ++in_degree[to];
    }
    for (int e = 0; e < cube::kEdges; ++e)
      if (edge_is_crossed(config, e)) {
        EXPECT_EQ(out_degree[e], 1) << "configuration " << config << ", edge " << e;
        EXPECT_EQ(in_degree[e], 1) << "configuration " << config << ", edge " << e;
      }
  }
}

// Lorensen and Cline reach every configuration from their 15 by rotation and complement; with
// uncomplemented images preferred, exactly those with more than four inner corners need the
// complement. Mirrors are tried with each base case, so the second staircase (the mirror image
// of the first) is reached from the first and its own entry is never needed.
TEST(MarchingCubesTable, ConfigurationsAboveFourInnerCornersAreComplementsOfBaseCases) {
  const MarchingCubesTable& table = marching_cubes_table();
  std::map<int, int> uncomplemented_per_base;
  for (unsigned config = 0; config < 256; ++config) {
    EXPECT_EQ(table.complemented[config], cube::inner_count(config) > 4) << config;
    if (!table.complemented[config]) ++uncomplemented_per_base[table.base[config]];
    EXPECT_LE(table.cases[config].triangle_count, 4) << "Lorensen and Cline use at most 4";
  }
  // Configurations per base case: corner subsets of each shape (1 + 8 + 28 + 56 + 70 = 163).
  const std::map<int, int> expected = {{0, 1},  {1, 8},   {2, 12},  {3, 12}, {4, 4},
                                       {5, 24}, {6, 24},  {7, 8},   {8, 6},  {9, 8},
                                       {10, 6}, {11, 24}, {12, 24}, {13, 2}};
  EXPECT_EQ(uncomplemented_per_base, expected);
  for (int base = 0; base < 15; ++base) EXPECT_STRNE(marching_cubes_base_name(base), "");
}

// ---------------------------------------------------------------------------------------------
// The engine.

EngineOptions cubes() {
  EngineOptions options;
  options.method = SurfaceMethod::cubes;
  return options;
}

Volume<float> sampled(const sim::Phantom& phantom) {
  const sim::Grid grid = phantom.grid();
  Volume<float> volume(grid.width, grid.height, grid.depth);
  volume.samples = sim::sample_volume(phantom);
  return volume;
}

// The configuration of the cube whose lowest voxel is (x, y, z); voxels outside are outer.
unsigned cube_config(const Volume<float>& volume, int x, int y, int z, double threshold) {
  unsigned config = 0;
  for (int c = 0; c < cube::kCorners; ++c) {
    const int vx = x + cube::corner_bit(c, 0), vy = y + cube::corner_bit(c, 1);
    const int vz = z + cube::corner_bit(c, 2);
    const bool inside = vx >= 0 && vy >= 0 && vz >= 0 && vx < int(volume.width) &&
                        vy < int(volume.height) && vz < int(volume.depth);
    if (inside && volume.at(vx, vy, vz) >= threshold) config |= 1u << c;
  }
  return config;
}

using CubeKey = std::array<int, 3>;

// The cube a polygon lies in: the floor of its centroid (never on a cube face, docs/design.md
// section 4).
CubeKey cube_of(const Mesh& mesh, const std::vector<std::uint32_t>& polygon) {
  double sum[3] = {};
  for (std::uint32_t index : polygon) {
    const Vertex& v = mesh.vertices[index];
    sum[0] += v.x;
    sum[1] += v.y;
    sum[2] += v.z;
  }
  const double n = static_cast<double>(polygon.size());
  return {static_cast<int>(std::floor(sum[0] / n)), static_cast<int>(std::floor(sum[1] / n)),
          static_cast<int>(std::floor(sum[2] / n))};
}

// Per cube, the directed sides of its polygons that no other polygon of the cube runs back
// along: for marching voxels the polygons' own sides, for marching cubes the boundary of the
// merged triangles.
std::map<CubeKey, std::multiset<std::pair<std::uint32_t, std::uint32_t>>> boundaries_by_cube(
    const Mesh& mesh) {
  std::map<CubeKey, std::multiset<std::pair<std::uint32_t, std::uint32_t>>> sides;
  for (const auto& polygon : mesh.polygons) {
    auto& cube_sides = sides[cube_of(mesh, polygon)];
    for (std::size_t i = 0; i < polygon.size(); ++i)
      cube_sides.insert({polygon[i], polygon[(i + 1) % polygon.size()]});
  }
  for (auto& [key, cube_sides] : sides) {
    std::multiset<std::pair<std::uint32_t, std::uint32_t>> boundary;
    for (const auto& [from, to] : cube_sides)
      if (cube_sides.count({to, from}) == 0) boundary.insert({from, to});
    cube_sides = boundary;
  }
  return sides;
}

// On 0/1 samples at threshold 1/2 every crossing is at a midpoint, so both methods emit the same
// vertices, and a cube's merged marching-cubes triangles must be bounded by its marching-voxels
// polygons wherever Lorensen and Cline's choice agrees with the merge rules.
TEST(MarchingCubesEngine,
     MergedTrianglesAreTheMarchingVoxelsPolygonsExceptOnComplementedAmbiguity) {
  std::set<unsigned> seen, differing;
  for (double density : {0.2, 0.35, 0.5, 0.65, 0.8}) {
    const sim::RandomVoxels phantom({22, 21, 20}, 11, density);
    const Volume<float> volume = sampled(phantom);
    const Mesh voxels = test::extract(volume, 0.5);
    const Mesh cubes_mesh = test::extract(volume, 0.5, cubes());
    ASSERT_EQ(voxels.vertices.size(), cubes_mesh.vertices.size());
    for (std::size_t i = 0; i < voxels.vertices.size(); ++i)
      ASSERT_TRUE(test::same_position(voxels.vertices[i], cubes_mesh.vertices[i])) << i;
    auto by_cube_voxels = boundaries_by_cube(voxels);
    auto by_cube_cubes = boundaries_by_cube(cubes_mesh);
    for (int z = -1; z < int(volume.depth); ++z)
      for (int y = -1; y < int(volume.height); ++y)
        for (int x = -1; x < int(volume.width); ++x) {
          const unsigned config = cube_config(volume, x, y, z, 0.5);
          if (config == 0 || config == 255) continue;
          seen.insert(config);
          const CubeKey key = {x, y, z};
          if (by_cube_voxels[key] != by_cube_cubes[key]) differing.insert(config);
        }
  }
  std::set<unsigned> expected;
  for (unsigned config : seen)
    if (has_ambiguous_face(config) && cube::inner_count(config) > 4) expected.insert(config);
  EXPECT_EQ(seen.size(), 254u) << "the volumes should hold every configuration";
  EXPECT_EQ(expected.size(), 44u);
  EXPECT_EQ(differing, expected);
  // The same 44 as the paper's Table 1 departs in (docs/surface_rules.md).
  for (unsigned config : differing) EXPECT_TRUE(paper_table1_applies(config)) << config;
  std::string list;
  for (unsigned config : differing) list += " " + std::to_string(config);
  std::printf("configurations where marching cubes and marching voxels differ (%zu):%s\n",
              differing.size(), list.c_str());
}

// Two cubes sharing a face with two diagonal inner corners disagree when exactly one of them
// was complemented: one joins the inner corners across the face, the other cuts them off, and
// four segments on that face have no partner. Counted from the volume alone, that predicts
// marching cubes' open edges exactly; marching voxels leaves none.
std::size_t predicted_open_edges(const Volume<float>& volume, double threshold) {
  std::size_t open = 0;
  for (int z = -1; z < int(volume.depth); ++z)
    for (int y = -1; y < int(volume.height); ++y)
      for (int x = -1; x < int(volume.width); ++x) {
        const unsigned config = cube_config(volume, x, y, z, threshold);
        for (int axis = 0; axis < 3; ++axis) {
          const int nx = x + (axis == 0), ny = y + (axis == 1), nz = z + (axis == 2);
          if (nx >= int(volume.width) || ny >= int(volume.height) || nz >= int(volume.depth))
            continue;
          const unsigned neighbour = cube_config(volume, nx, ny, nz, threshold);
          if (!cube::face_is_ambiguous(config, 2 * axis + 1)) continue;
          if ((cube::inner_count(config) > 4) != (cube::inner_count(neighbour) > 4)) open += 4;
        }
      }
  return open;
}

TEST(MarchingCubesEngine, OpenEdgesOnRandomVolumesAreExactlyTheComplementedAmbiguities) {
  std::printf("%-8s %-12s %-22s %-22s\n", "density", "volume", "marching cubes open",
              "voxels open");
  for (double density : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    const sim::RandomVoxels phantom({24, 20, 18}, 5, density);
    const Volume<float> volume = sampled(phantom);
    const test::Topology cubes_topology = test::analyse(test::extract(volume, 0.5, cubes()));
    const test::Topology voxels_topology = test::analyse(test::extract(volume, 0.5));
    const std::size_t predicted = predicted_open_edges(volume, 0.5);
    EXPECT_EQ(cubes_topology.open_edges, predicted) << "density " << density;
    EXPECT_EQ(cubes_topology.repeated_edges, 0u) << "density " << density;
    EXPECT_TRUE(voxels_topology.closed_and_consistent())
        << "density " << density << ": " << test::describe(voxels_topology);
    std::printf("%-8.1f %-12s %-22zu %-22zu\n", density, "24x20x18", cubes_topology.open_edges,
                voxels_topology.open_edges);
    if (density >= 0.5) EXPECT_GT(predicted, 0u) << "density " << density;
  }
}

// Without an ambiguous face, marching cubes is closed and wound outward like marching voxels.
TEST(MarchingCubesEngine, ASmoothObjectGivesAClosedOutwardWoundSurface) {
  for (const char* name : {"sphere", "torus", "blobs"}) {
    const auto phantom = sim::make_phantom(name, {30, 28, 26}, 4);
    const Volume<float> volume = sampled(*phantom);
    const double threshold = sim::default_density_threshold(name);
    const test::Topology topology = test::analyse(test::extract(volume, threshold, cubes()));
    const test::Topology voxels = test::analyse(test::extract(volume, threshold));
    EXPECT_EQ(topology.repeated_edges, 0u) << name;
    EXPECT_EQ(topology.degenerate_polygons, 0u) << name;
    EXPECT_GT(topology.signed_volume, 0) << name;
    if (predicted_open_edges(volume, threshold) == 0)
      EXPECT_TRUE(topology.closed_and_consistent()) << name << ": " << test::describe(topology);
    // Same vertices, so the same Euler characteristic wherever the surface is closed.
    EXPECT_EQ(topology.vertices, voxels.vertices) << name;
  }
}

// A linear density is interpolated exactly: every vertex between two voxels of the volume sits
// where the density equals the threshold.
TEST(MarchingCubesEngine, VerticesSitWhereTheInterpolatedSamplesCrossTheThreshold) {
  Volume<float> volume(13, 11, 9);
  auto density = [](double x, double y, double z) { return 0.7 * x + 0.45 * y - 0.3 * z; };
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    for (std::uint32_t y = 0; y < volume.height; ++y)
      for (std::uint32_t x = 0; x < volume.width; ++x)
        volume.at(x, y, z) = static_cast<float>(density(x, y, z));
  const double threshold = 5.3;
  const Mesh mesh = test::extract(volume, threshold, cubes());
  std::size_t inside = 0;
  for (const Vertex& v : mesh.vertices) {
    const double c[3] = {v.x, v.y, v.z};
    const double extent[3] = {double(volume.width), double(volume.height), double(volume.depth)};
    bool within = true;
    for (int axis = 0; axis < 3; ++axis)
      within = within && c[axis] >= 0 && c[axis] <= extent[axis] - 1;
    if (!within) {
      // A pair with a voxel outside keeps its midpoint.
      const double along = c[static_cast<int>(v.axis)];
      EXPECT_EQ(along - std::floor(along), 0.5);
      continue;
    }
    ++inside;
    EXPECT_NEAR(density(v.x, v.y, v.z), threshold, 1e-4) << v.x << "," << v.y << "," << v.z;
  }
  EXPECT_GT(inside, 100u);
}

// On a distance field, interpolated vertices (marching cubes', and marching voxels' with
// --interpolate) lie on the sphere to within the interpolation's second-order error; midpoints
// (marching voxels) are off by up to half a voxel.
TEST(MarchingCubesEngine, InterpolatedVerticesLieOnTheSphereMidpointsDoNot) {
  const double radius = 8.3, centre = 10.4;
  Volume<float> volume(21, 21, 21);
  auto distance = [&](double x, double y, double z) {
    return std::sqrt((x - centre) * (x - centre) + (y - centre) * (y - centre) +
                     (z - centre) * (z - centre));
  };
  for (std::uint32_t z = 0; z < volume.depth; ++z)
    for (std::uint32_t y = 0; y < volume.height; ++y)
      for (std::uint32_t x = 0; x < volume.width; ++x)
        volume.at(x, y, z) = static_cast<float>(radius - distance(x, y, z));
  auto worst_error = [&](const Mesh& mesh) {
    double worst = 0;
    for (const Vertex& v : mesh.vertices)
      worst = std::max(worst, std::abs(distance(v.x, v.y, v.z) - radius));
    return worst;
  };
  EngineOptions interpolated;
  interpolated.interpolate = true;
  EXPECT_LT(worst_error(test::extract(volume, 0.0, cubes())), 0.05);
  EXPECT_LT(worst_error(test::extract(volume, 0.0, interpolated)), 0.05);
  EXPECT_GT(worst_error(test::extract(volume, 0.0)), 0.3);
}

TEST(MarchingCubesEngine, WorkspaceAddsTwoSlicesOfSamplesAndRefusesMarchingVoxelsOptions) {
  for (auto [w, h] : {std::pair<std::uint32_t, std::uint32_t>{256, 256}, {1000, 3}}) {
    const std::size_t voxels = engine_workspace_bytes(w, h, EngineOptions());
    const std::size_t with_samples = engine_workspace_bytes(w, h, cubes());
    EXPECT_GE(with_samples - voxels, std::size_t{8} * w * h);
    EXPECT_LT(with_samples - voxels, std::size_t{8} * w * h + 2 * kWorkspaceAlignment);
  }
  EngineOptions literal = cubes();
  literal.kind = EngineKind::literal;
  EXPECT_EQ(engine_workspace_bytes(16, 16, literal), 0u);
  EngineOptions table1 = cubes();
  table1.rule = SurfaceRule::paper_table1;
  EXPECT_EQ(engine_workspace_bytes(16, 16, table1), 0u);
}

// The samples kept for interpolation are read back in their own type.
TEST(MarchingCubesEngine, SampleTypesInterpolateAlike) {
  const std::vector<float> coarse = sim::sample_volume(sim::RandomVoxels({9, 8, 7}, 3, 0.5));
  const std::vector<float> fine = sim::sample_volume(sim::RandomVoxels({9, 8, 7}, 4, 0.5));
  Volume<float> real(9, 8, 7);
  Volume<std::uint16_t> integer(9, 8, 7);
  for (std::size_t i = 0; i < real.samples.size(); ++i) {
    integer.samples[i] = static_cast<std::uint16_t>(100 + 800 * coarse[i] + 37 * fine[i]);
    real.samples[i] = static_cast<float>(integer.samples[i]);
  }
  const Mesh from_float = test::extract(real, 500, cubes());
  const Mesh from_u16 = test::extract(integer, 500, cubes());
  ASSERT_EQ(from_float.vertices.size(), from_u16.vertices.size());
  for (std::size_t i = 0; i < from_float.vertices.size(); ++i)
    EXPECT_TRUE(test::same_position(from_float.vertices[i], from_u16.vertices[i])) << i;
  EXPECT_EQ(from_float.polygons, from_u16.polygons);
}

}  // namespace
}  // namespace mvox
