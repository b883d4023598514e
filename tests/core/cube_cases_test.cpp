// Exhaustive checks on the smallest volumes: every configuration of one cube and of two
// face-adjacent cubes, and the case table against the face rule stated in docs/design.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "case_table.h"
#include "cube.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"

namespace mvox {
namespace {

using test::analyse;
using test::describe;
using test::extract;
using test::volume_from_bits;

EngineOptions with(EngineKind kind, SurfaceRule rule = SurfaceRule::merge_rules) {
  EngineOptions options;
  options.kind = kind;
  options.rule = rule;
  return options;
}

// Checks everything a merge-rules surface of `volume` must satisfy, for both engines.
// `simply_connected`: the inner voxels can form no tunnel (true for one cube; two cubes side by
// side can already hold a ring of voxels around an outer one, a torus).
void expect_valid_surface(const test::BinaryVolume& volume, const std::string& label,
                          bool simply_connected) {
  const test::Mesh fast = extract(volume, 1, with(EngineKind::fast));
  const test::Mesh literal = extract(volume, 1, with(EngineKind::literal));
  ASSERT_TRUE(test::meshes_identical(fast, literal)) << label;

  const test::Topology topology = analyse(fast);
  EXPECT_TRUE(topology.closed_and_consistent()) << label << ": " << describe(topology);
  EXPECT_EQ(fast.forward_references, 0u) << label;
  // A closed orientable surface has an even Euler characteristic, at most 2 per component
  // (2 - 2 * genus); a sphere per component when there can be no tunnel.
  const std::int64_t spheres = 2 * static_cast<std::int64_t>(topology.components);
  EXPECT_EQ(topology.euler() % 2, 0) << label << ": " << describe(topology);
  if (simply_connected)
    EXPECT_EQ(topology.euler(), spheres) << label << ": " << describe(topology);
  else
    EXPECT_LE(topology.euler(), spheres) << label << ": " << describe(topology);
  if (!fast.polygons.empty()) EXPECT_GT(topology.signed_volume, 0) << label;

  const std::vector<Vertex> expected = test::expected_vertices(volume);
  const std::vector<Vertex> actual = test::sorted_positions(fast);
  ASSERT_EQ(actual.size(), expected.size()) << label;
  for (std::size_t i = 0; i < actual.size(); ++i)
    ASSERT_TRUE(test::same_position(actual[i], expected[i])) << label << " vertex " << i;
}

TEST(CubeCases, EverySingleCubeConfigurationIsClosedAndConsistent) {
  // Voxel i of the 2x2x2 volume (x fastest) is cube corner i, so `config` is the cube's case.
  for (unsigned config = 0; config < 256; ++config)
    expect_valid_surface(volume_from_bits(2, 2, 2, config), "config " + std::to_string(config),
                         true);
}

TEST(CubeCases, EveryPairOfFaceAdjacentCubesIsClosedAndConsistent) {
  const std::uint32_t shapes[3][3] = {{3, 2, 2}, {2, 3, 2}, {2, 2, 3}};
  for (const auto& shape : shapes)
    for (std::uint64_t bits = 0; bits < 4096; ++bits)
      expect_valid_surface(volume_from_bits(shape[0], shape[1], shape[2], bits),
                           std::to_string(shape[0]) + "x" + std::to_string(shape[1]) + "x" +
                               std::to_string(shape[2]) + " bits " + std::to_string(bits),
                           false);
}

// The face rule (docs/design.md, "What the merge rules produce"): on each cube face the surface
// depends only on the face's four voxels. One inner corner: a segment cutting it off; two
// adjacent: one straight segment; two diagonal: two segments, one cutting off each inner corner;
// three: a segment cutting off the outer corner. This oracle is written from that statement
// alone, not from the merge code, and checked against the generated table.
using Segment = std::pair<int, int>;  // unordered pair of cube-edge ids, smaller first

std::set<Segment> face_rule_segments(unsigned config, int face) {
  int corner[4], edge_after[4];  // edge_after[i] joins corner i and corner i + 1 (cyclic)
  for (int i = 0; i < 4; ++i) corner[i] = cube::face_corner(face, i);
  for (int i = 0; i < 4; ++i)
    for (int e = 0; e < cube::kEdges; ++e) {
      const int lo = cube::edge_low_corner(e), hi = cube::edge_high_corner(e);
      const int a = corner[i], b = corner[(i + 1) % 4];
      if ((lo == a && hi == b) || (lo == b && hi == a)) edge_after[i] = e;
    }
  auto inner = [&](int i) { return (config >> corner[(i + 4) % 4] & 1) != 0; };
  auto cut_corner = [&](int i) {  // the segment between the two edges meeting at corner i
    const int e1 = edge_after[(i + 3) % 4], e2 = edge_after[i];
    return Segment(std::min(e1, e2), std::max(e1, e2));
  };
  int count = 0;
  for (int i = 0; i < 4; ++i) count += inner(i);
  std::set<Segment> segments;
  if (count == 1 || count == 3) {
    for (int i = 0; i < 4; ++i)
      if (inner(i) == (count == 1)) segments.insert(cut_corner(i));
  } else if (count == 2) {
    if (inner(0) == inner(2)) {  // diagonal: cut off each inner corner separately
      for (int i = 0; i < 4; ++i)
        if (inner(i)) segments.insert(cut_corner(i));
    } else {  // adjacent: one segment between the two edges that change sign
      std::vector<int> crossing;
      for (int i = 0; i < 4; ++i)
        if (inner(i) != inner(i + 1)) crossing.push_back(edge_after[i]);
      segments.insert({std::min(crossing[0], crossing[1]), std::max(crossing[0], crossing[1])});
    }
  }
  return segments;
}

TEST(CaseTable, MatchesTheFaceRuleOnEveryFaceOfEveryConfiguration) {
  const CaseTable& table = case_table(SurfaceRule::merge_rules);
  for (unsigned config = 0; config < 256; ++config) {
    std::set<Segment> by_face[cube::kFaces];
    const CubePolygons& polygons = table.cases[config];
    int offset = 0;
    for (int p = 0; p < polygons.polygon_count; ++p) {
      const int size = polygons.polygon_sizes[p];
      for (int i = 0; i < size; ++i) {
        const int a = polygons.edges[offset + i], b = polygons.edges[offset + (i + 1) % size];
        const int face = cube::shared_face(a, b);
        ASSERT_GE(face, 0) << "config " << config << ": segment off the cube faces";
        by_face[face].insert({std::min(a, b), std::max(a, b)});
      }
      offset += size;
    }
    for (int face = 0; face < cube::kFaces; ++face)
      EXPECT_EQ(by_face[face], face_rule_segments(config, face))
          << "config " << config << " face " << face;
  }
}

TEST(CaseTable, PolygonsHaveThreeToSevenVerticesAndUseEachEdgeOnce) {
  const CaseTable& table = case_table(SurfaceRule::merge_rules);
  int sizes[8] = {};
  for (unsigned config = 0; config < 256; ++config) {
    const CubePolygons& polygons = table.cases[config];
    std::set<int> edges(polygons.edges, polygons.edges + polygons.edge_count);
    EXPECT_EQ(edges.size(), polygons.edge_count) << "config " << config;
    // Exactly the edges between an inner and an outer corner carry a vertex.
    int crossing = 0;
    for (int e = 0; e < cube::kEdges; ++e)
      crossing +=
          (config >> cube::edge_low_corner(e) & 1) != (config >> cube::edge_high_corner(e) & 1);
    EXPECT_EQ(polygons.edge_count, crossing) << "config " << config;
    for (int p = 0; p < polygons.polygon_count; ++p) ++sizes[polygons.polygon_sizes[p]];
  }
  for (int size = 3; size <= 7; ++size) EXPECT_GT(sizes[size], 0) << "no polygon of size " << size;
}

// The configurations where the paper's Table 1 departs from the merge rules, described by the
// geometry of their outer voxels alone (docs/surface_rules.md), without the code's predicate.
// Corners a and b share a cube edge when they differ in one coordinate, a face diagonal in two.
int corner_distance(int a, int b) { return cube::inner_count(static_cast<unsigned>(a ^ b)); }

std::set<unsigned> configurations_the_paper_changes(int* edge_pair_plus_far, int* diagonal_triple,
                                                    int* diagonal_pair) {
  std::set<unsigned> result;
  for (unsigned config = 0; config < 256; ++config) {
    std::vector<int> outer;
    for (int c = 0; c < 8; ++c)
      if (!(config >> c & 1)) outer.push_back(c);
    if (outer.size() == 3) {
      int adjacent_pairs = 0, diagonal_pairs = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j) {
          adjacent_pairs += corner_distance(outer[i], outer[j]) == 1;
          diagonal_pairs += corner_distance(outer[i], outer[j]) == 2;
        }
      if (adjacent_pairs == 1) {  // an edge pair, the third outer voxel touching neither
        ++*edge_pair_plus_far;
        result.insert(config);
      } else if (diagonal_pairs == 3) {  // three outer voxels, pairwise face-diagonal
        ++*diagonal_triple;
        result.insert(config);
      }
    } else if (outer.size() == 2 && corner_distance(outer[0], outer[1]) == 2) {
      ++*diagonal_pair;
      result.insert(config);
    }
  }
  return result;
}

// The renderer draws a polygon as a fan of triangles from its first vertex. For a non-planar
// loop any fan is a surface spanning it; for a planar one the fan stays inside the polygon only
// if every triangle of it turns the same way (the first vertex sees all the others). This
// checks that for every planar polygon of every configuration, with both surface rules.
TEST(CaseTable, EveryPlanarPolygonIsCoveredExactlyByTheFanFromItsFirstVertex) {
  auto midpoint = [](int e) {
    const int low = cube::edge_low_corner(e), high = cube::edge_high_corner(e);
    std::array<double, 3> p{};
    for (int axis = 0; axis < 3; ++axis)
      p[axis] = 0.5 * (cube::corner_bit(low, axis) + cube::corner_bit(high, axis));
    return p;
  };
  auto sub = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  };
  auto cross = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                 a[0] * b[1] - a[1] * b[0]};
  };
  auto dot = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  int planar = 0, non_planar = 0;
  for (const SurfaceRule rule : {SurfaceRule::merge_rules, SurfaceRule::paper_table1}) {
    for (unsigned config = 0; config < 256; ++config) {
      const CubePolygons& polygons = case_table(rule).cases[config];
      int offset = 0;
      for (int p = 0; p < polygons.polygon_count; ++p) {
        const int n = polygons.polygon_sizes[p];
        std::vector<std::array<double, 3>> v;
        for (int i = 0; i < n; ++i) v.push_back(midpoint(polygons.edges[offset + i]));
        offset += n;
        // Newell's normal; planar when every vertex lies in the plane through the first.
        std::array<double, 3> normal{};
        for (int i = 0; i < n; ++i) {
          const auto c = cross(v[i], v[(i + 1) % n]);
          for (int axis = 0; axis < 3; ++axis) normal[axis] += c[axis];
        }
        bool is_planar = true;
        for (int i = 1; i < n; ++i)
          is_planar = is_planar && std::abs(dot(normal, sub(v[i], v[0]))) < 1e-9;
        if (!is_planar) {
          ++non_planar;
          continue;
        }
        ++planar;
        for (int i = 1; i + 1 < n; ++i)
          EXPECT_GT(dot(cross(sub(v[i], v[0]), sub(v[i + 1], v[0])), normal), 1e-9)
              << "configuration " << config << ", polygon " << p << ", fan triangle " << i;
      }
    }
  }
  EXPECT_GT(planar, 0);
  std::printf("planar polygons %d, non-planar %d (both rules)\n", planar, non_planar);
}

TEST(PaperTable1, DiffersFromTheMergeRulesExactlyInTheConfigurationsTheDocsDescribe) {
  const CaseTable& merge = case_table(SurfaceRule::merge_rules);
  const CaseTable& paper = case_table(SurfaceRule::paper_table1);
  std::set<unsigned> differing;
  for (unsigned config = 0; config < 256; ++config) {
    const CubePolygons &a = merge.cases[config], &b = paper.cases[config];
    const bool same =
        a.polygon_count == b.polygon_count && a.edge_count == b.edge_count &&
        std::equal(a.polygon_sizes, a.polygon_sizes + a.polygon_count, b.polygon_sizes) &&
        std::equal(a.edges, a.edges + a.edge_count, b.edges);
    if (!same) differing.insert(config);
  }
  int edge_pair_plus_far = 0, diagonal_triple = 0, diagonal_pair = 0;
  EXPECT_EQ(differing, configurations_the_paper_changes(&edge_pair_plus_far, &diagonal_triple,
                                                        &diagonal_pair));
  EXPECT_EQ(differing.size(), 44u);
  EXPECT_EQ(edge_pair_plus_far, 24);
  EXPECT_EQ(diagonal_triple, 8);
  EXPECT_EQ(diagonal_pair, 12);
}

// Each of those 44 cubes, alone in a 2x2x2 volume, meets its neighbouring (outside) cube across
// an ambiguous face. The neighbour follows the merge rules and keeps the two inner voxels apart;
// the paper's complementary surface joins them: the two faces disagree and a hole opens.
TEST(PaperTable1, OpensHolesWhereTheMergeRulesGiveAClosedSurface) {
  int configurations_with_holes = 0;
  for (unsigned config = 0; config < 256; ++config) {
    if (!paper_table1_applies(config)) continue;
    const test::BinaryVolume volume = volume_from_bits(2, 2, 2, config);
    const test::Mesh paper_fast =
        extract(volume, 1, with(EngineKind::fast, SurfaceRule::paper_table1));
    const test::Mesh paper_literal =
        extract(volume, 1, with(EngineKind::literal, SurfaceRule::paper_table1));
    ASSERT_TRUE(test::meshes_identical(paper_fast, paper_literal)) << "config " << config;
    const test::Topology merge = analyse(extract(volume, 1));
    const test::Topology paper = analyse(paper_fast);
    EXPECT_EQ(merge.open_edges, 0u) << "config " << config;
    EXPECT_GT(paper.open_edges, 0u) << "config " << config << ": " << describe(paper);
    configurations_with_holes += paper.open_edges > 0;
  }
  EXPECT_EQ(configurations_with_holes, 44);
}

}  // namespace
}  // namespace mvox
