// --triangulate (src/write/mesh/polygon_triangulation.h): every polygon of all 256 cube
// configurations, for both surface rules, splits into triangles whose diagonals run inside the
// cube; marching cubes' own triangles already do; and on random volumes holding every configuration
// the triangulated file is closed, edge-manifold and consistently wound, and each polygon's
// triangles cover it.
#include "write/mesh/polygon_triangulation.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "case_table.h"
#include "command_runner.h"
#include "cube.h"
#include "marching_cubes_table.h"
#include "mesh_capture.h"
#include "mesh_topology.h"
#include "mvox/fan_out_sink.h"
#include "random_phantoms.h"
#include "read/ply/ply_reader.h"
#include "simulated_scanner.h"
#include "write/mesh/ply_writer.h"

namespace mvox {
namespace {

using Point = std::array<double, 3>;

// A cube away from the origin, so that its faces are planes x = 5, 6, y = 7, 8, z = 11, 12.
constexpr int kCubeAt[3] = {5, 7, 11};

// The midpoint of cube edge `e` (cube.h), in voxel units.
Vertex edge_midpoint(int e) {
  const int low = cube::edge_low_corner(e), high = cube::edge_high_corner(e);
  float position[3];
  for (int axis = 0; axis < 3; ++axis)
    position[axis] =
        kCubeAt[axis] + 0.5f * float(cube::corner_bit(low, axis) + cube::corner_bit(high, axis));
  Vertex v;
  v.x = position[0];
  v.y = position[1];
  v.z = position[2];
  v.axis = static_cast<Axis>(cube::edge_axis(e));
  return v;
}

Point point(const Vertex& v) { return {v.x, v.y, v.z}; }

Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Twice the vector area of a closed loop: sum of p_i x p_i+1. Exact in double for the
// half-integer positions used here.
Point doubled_vector_area(const std::vector<Point>& loop) {
  Point sum = {0, 0, 0};
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point c = cross(loop[i], loop[(i + 1) % loop.size()]);
    for (int k = 0; k < 3; ++k) sum[k] += c[k];
  }
  return sum;
}

// Written apart from on_common_cube_face(), from docs/design.md's definition: a cube face is a
// plane x = c, y = c or z = c with c an integer.
bool share_an_integer_plane(const Point& a, const Point& b) {
  for (int k = 0; k < 3; ++k)
    if (a[k] == b[k] && a[k] == std::floor(a[k])) return true;
  return false;
}
bool in_one_integer_plane(const Point& a, const Point& b, const Point& c) {
  for (int k = 0; k < 3; ++k)
    if (a[k] == b[k] && b[k] == c[k] && a[k] == std::floor(a[k])) return true;
  return false;
}

TEST(PolygonTriangulation, CommonCubeFaceIsTheCubeGeometrysSharedFace) {
  for (int e1 = 0; e1 < cube::kEdges; ++e1)
    for (int e2 = 0; e2 < cube::kEdges; ++e2)
      if (e1 != e2)
        EXPECT_EQ(on_common_cube_face(edge_midpoint(e1), edge_midpoint(e2)),
                  cube::shared_face(e1, e2) != -1)
            << "edges " << e1 << " and " << e2;
}

// What a triangulation of `polygon` (edge ids around it) must be: n - 2 triangles wound as the
// polygon; each polygon side in exactly one triangle, each diagonal in exactly two, in opposite
// directions; no diagonal between edges on one face (cube.h says which); no triangle in a face;
// the triangles' vector areas summing to the polygon's.
void expect_good_triangulation(const std::vector<int>& polygon, const PolygonTriangles& triangles,
                               const std::string& where) {
  const int n = static_cast<int>(polygon.size());
  ASSERT_EQ(triangles.count, n - 2) << where;
  std::map<std::pair<int, int>, int> sides;  // directed, in polygon positions
  Point area = {0, 0, 0};
  for (int t = 0; t < triangles.count; ++t) {
    const std::uint8_t* c = triangles.corners[t];
    ASSERT_TRUE(c[0] < n && c[1] < n && c[2] < n) << where;
    ASSERT_TRUE(c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) << where;
    for (int f = 0; f < cube::kFaces; ++f)
      EXPECT_FALSE(cube::edge_on_face(polygon[c[0]], f) && cube::edge_on_face(polygon[c[1]], f) &&
                   cube::edge_on_face(polygon[c[2]], f))
          << where << ": triangle " << t << " lies in face " << f;
    for (int k = 0; k < 3; ++k) ++sides[{c[k], c[(k + 1) % 3]}];
    const Point a = doubled_vector_area({point(edge_midpoint(polygon[c[0]])),
                                         point(edge_midpoint(polygon[c[1]])),
                                         point(edge_midpoint(polygon[c[2]]))});
    for (int k = 0; k < 3; ++k) area[k] += a[k];
  }
  for (const auto& [side, count] : sides) {
    const auto [from, to] = side;
    EXPECT_EQ(count, 1) << where << ": side " << from << "-" << to << " repeated";
    const bool polygon_side = to == (from + 1) % n;
    if (polygon_side) continue;
    EXPECT_NE(from, (to + 1) % n) << where << ": a polygon side walked backwards";
    EXPECT_EQ(sides.count({to, from}), 1u) << where << ": diagonal without its partner";
    EXPECT_EQ(cube::shared_face(polygon[from], polygon[to]), -1)
        << where << ": diagonal " << from << "-" << to << " joins two vertices on one face";
  }
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(sides.count({i, (i + 1) % n}), 1u) << where << ": polygon side " << i << " missing";
  std::vector<Point> loop;
  for (int e : polygon) loop.push_back(point(edge_midpoint(e)));
  EXPECT_EQ(area, doubled_vector_area(loop)) << where;
}

TEST(PolygonTriangulation, EveryPolygonOfBothSurfaceRulesSplitsInsideItsCube) {
  for (SurfaceRule rule : {SurfaceRule::merge_rules, SurfaceRule::paper_table1}) {
    const char* rule_name = rule == SurfaceRule::merge_rules ? "merge-rules" : "paper-table1";
    std::size_t polygons = 0, triangles_made = 0, naive_fan_fails = 0;
    for (unsigned config = 0; config < 256; ++config) {
      const CubePolygons& cube_polygons = case_table(rule).cases[config];
      int offset = 0;
      for (int p = 0; p < cube_polygons.polygon_count; ++p) {
        const int n = cube_polygons.polygon_sizes[p];
        std::vector<int> edges(cube_polygons.edges + offset, cube_polygons.edges + offset + n);
        offset += n;
        PolygonGeometry geometry;
        geometry.vertex_count = static_cast<std::uint8_t>(n);
        for (int k = 0; k < n; ++k) geometry.vertices[k] = edge_midpoint(edges[k]);
        PolygonTriangles triangles;
        const std::string where = std::string(rule_name) + " configuration " +
                                  std::to_string(config) + " polygon " + std::to_string(p);
        ASSERT_TRUE(triangulate_polygon(geometry, &triangles)) << where;
        expect_good_triangulation(edges, triangles, where);
        ++polygons;
        triangles_made += triangles.count;
        // Two vertices that are not neighbours share a face only where the loop crosses an
        // ambiguous face twice (docs/surface_rules.md says so).
        for (int i = 0; i < n; ++i)
          for (int j = i + 2; j < n && j - i < n - 1; ++j)
            if (const int face = cube::shared_face(edges[i], edges[j]); face != -1)
              EXPECT_TRUE(cube::face_is_ambiguous(config, face)) << where;
        // Would the fan from vertex 0 have done? Counted to show the choice matters.
        for (int k = 2; k <= n - 2; ++k)
          if (cube::shared_face(edges[0], edges[k]) != -1) {
            ++naive_fan_fails;
            break;
          }
      }
    }
    std::printf(
        "%s: %zu polygons in 256 configurations -> %zu triangles; the fan from vertex 0 "
        "would put a diagonal on a cube face in %zu of them\n",
        rule_name, polygons, triangles_made, naive_fan_fails);
    EXPECT_GT(polygons, 256u);
    if (rule == SurfaceRule::merge_rules) EXPECT_GT(naive_fan_fails, 0u);
  }
}

// Marching cubes emits triangles, which --triangulate leaves alone: its table never puts one in a
// cube face, and the sides two triangles of one cube share (its own diagonals) run inside.
TEST(PolygonTriangulation, MarchingCubesTrianglesAlreadyAvoidTheCubeFaces) {
  const MarchingCubesTable& table = marching_cubes_table();
  std::size_t inner_sides = 0;
  for (unsigned config = 0; config < 256; ++config) {
    const MarchingCubesCase& c = table.cases[config];
    std::set<std::pair<int, int>> sides;
    for (int t = 0; t < c.triangle_count; ++t) {
      const std::uint8_t* e = c.edges + 3 * t;
      for (int f = 0; f < cube::kFaces; ++f)
        EXPECT_FALSE(cube::edge_on_face(e[0], f) && cube::edge_on_face(e[1], f) &&
                     cube::edge_on_face(e[2], f))
            << "configuration " << config << " triangle " << t;
      for (int k = 0; k < 3; ++k) sides.insert({e[k], e[(k + 1) % 3]});
    }
    for (const auto& [from, to] : sides)
      if (sides.count({to, from})) {
        ++inner_sides;
        EXPECT_EQ(cube::shared_face(from, to), -1) << "configuration " << config;
      }
  }
  EXPECT_GT(inner_sides, 0u);
}

TEST(PolygonTriangulation, RefusesWhatIsNotAPolygon) {
  PolygonTriangles triangles;
  PolygonGeometry geometry;
  for (std::uint8_t count : {0, 1, 2, 8}) {
    geometry.vertex_count = count;
    EXPECT_FALSE(triangulate_polygon(geometry, &triangles)) << int{count};
    EXPECT_EQ(triangles.count, 0);
  }
  // A square in the face z = 0: every diagonal joins two vertices on that face.
  geometry.vertex_count = 4;
  const float square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    geometry.vertices[k].x = square[k][0] + 0.5f;
    geometry.vertices[k].y = square[k][1];
    geometry.vertices[k].z = 0;
  }
  EXPECT_FALSE(triangulate_polygon(geometry, &triangles));
}

// A shared coordinate counts as a cube face exactly when floor() says it is a whole number,
// also where the check without floor changes method (2^23) and for the values floor treats
// alone: -0, infinities, NaN, and floats too large for 32-bit integers.
TEST(PolygonTriangulation, ACommonCubeFaceIsAWholeSharedCoordinateByFloorsDefinition) {
  const float two23 = 8388608.0f;
  const float values[] = {0.0f,
                          -0.0f,
                          0.5f,
                          -0.5f,
                          -3.0f,
                          -2.5f,
                          7.0f,
                          0.49999997f,
                          1.0000001f,
                          std::nextafter(two23, 0.0f),
                          two23 - 0.5f,
                          two23,
                          -two23,
                          two23 + 2.0f,
                          3e9f,
                          -3e9f,
                          1e30f,
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::denorm_min()};
  for (const float value : values)
    for (int axis = 0; axis < 3; ++axis) {
      // The two vertices share only this coordinate.
      Vertex a{1.25f, 2.25f, 3.25f}, b{4.75f, 5.75f, 6.75f};
      float* pa[3] = {&a.x, &a.y, &a.z};
      float* pb[3] = {&b.x, &b.y, &b.z};
      *pa[axis] = *pb[axis] = value;
      EXPECT_EQ(on_common_cube_face(a, b), std::floor(value) == value)
          << value << " on axis " << axis;
    }
}

// RANDOM VOLUMES -------------------------------------------------------------------------------

// The configuration of the cube whose lowest corner is voxel (x, y, z) (-1 .. size - 1).
unsigned cube_config(const std::vector<float>& samples, const sim::Grid& grid, int x, int y,
                     int z) {
  unsigned config = 0;
  for (int c = 0; c < cube::kCorners; ++c) {
    const int vx = x + cube::corner_bit(c, 0), vy = y + cube::corner_bit(c, 1);
    const int vz = z + cube::corner_bit(c, 2);
    const bool inside = vx >= 0 && vy >= 0 && vz >= 0 && vx < int(grid.width) &&
                        vy < int(grid.height) && vz < int(grid.depth);
    if (inside && samples[(std::size_t(vz) * grid.height + vy) * grid.width + vx] >= 0.5f)
      config |= 1u << c;
  }
  return config;
}

TEST(PolygonTriangulation, RandomVolumesGiveClosedManifoldTrianglesThatCoverEachPolygon) {
  const sim::Grid grid = {22, 21, 20};
  std::set<unsigned> configurations;
  for (SurfaceRule rule : {SurfaceRule::merge_rules, SurfaceRule::paper_table1}) {
    for (double density : {0.2, 0.35, 0.5, 0.65, 0.8}) {
      const std::string where =
          std::string(rule == SurfaceRule::merge_rules ? "merge-rules" : "paper-table1") +
          " density " + std::to_string(density);
      SCOPED_TRACE(where);
      const sim::RandomVoxels phantom(grid, 11, density);
      if (rule == SurfaceRule::merge_rules) {
        const std::vector<float> samples = sim::sample_volume(phantom);
        for (int z = -1; z < int(grid.depth); ++z)
          for (int y = -1; y < int(grid.height); ++y)
            for (int x = -1; x < int(grid.width); ++x)
              configurations.insert(cube_config(samples, grid, x, y, z));
      }
      test::ScratchDirectory dir;
      test::MeshCapture polygons;
      PlyWriterOptions options;
      options.triangulate = true;
      PlyWriter writer(dir / "triangles.ply", options);
      FanOutSink tee;  // the engine's polygons as they are, and the writer
      tee.add(&polygons);
      tee.add(&writer);
      EngineOptions engine;
      engine.rule = rule;
      engine.polygon_geometry = true;
      sim::SimulatedScanner scanner(phantom);
      {
        test::Workspace workspace(engine_workspace_bytes(grid.width, grid.height, engine));
        Engine e;
        ASSERT_EQ(
            e.init(workspace.data(), workspace.bytes(), grid.width, grid.height, 128, engine, &tee),
            Status::ok);
        SliceView slice;
        while (scanner.next_slice(&slice)) ASSERT_EQ(e.push_slice(slice), Status::ok);
        ASSERT_EQ(e.finish(), Status::ok);
      }
      writer.finish();
      const PlyMesh ply = read_ply(dir / "triangles.ply");
      const test::Mesh& original = polygons.mesh;

      // Each polygon of n vertices became the next n - 2 faces, triangles of its own vertices.
      ASSERT_EQ(ply.positions.size(), original.vertices.size());
      std::size_t face = 0;
      std::set<std::pair<std::uint32_t, std::uint32_t>> polygon_sides;
      for (const auto& polygon : original.polygons)
        for (std::size_t k = 0; k < polygon.size(); ++k)
          polygon_sides.insert({polygon[k], polygon[(k + 1) % polygon.size()]});
      auto position = [&](std::uint32_t i) -> Point {
        return {ply.positions[i][0], ply.positions[i][1], ply.positions[i][2]};
      };
      test::Mesh triangles;
      triangles.vertices = original.vertices;
      std::size_t diagonals = 0;
      for (std::size_t p = 0; p < original.polygons.size(); ++p) {
        const auto& polygon = original.polygons[p];
        const std::set<std::uint32_t> own(polygon.begin(), polygon.end());
        Point area = {0, 0, 0};
        for (std::size_t t = 0; t + 2 < polygon.size(); ++t, ++face) {
          ASSERT_LT(face, ply.face_count());
          ASSERT_EQ(ply.face_offsets[face + 1] - ply.face_offsets[face], 3u) << "face " << face;
          const std::uint32_t* c = &ply.face_indices[ply.face_offsets[face]];
          for (int k = 0; k < 3; ++k) ASSERT_TRUE(own.count(c[k])) << "polygon " << p;
          EXPECT_FALSE(in_one_integer_plane(position(c[0]), position(c[1]), position(c[2])))
              << "polygon " << p << " triangle " << t << " lies in a cube face";
          for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = c[k], b = c[(k + 1) % 3];
            if (polygon_sides.count({a, b})) continue;
            ++diagonals;
            EXPECT_FALSE(share_an_integer_plane(position(a), position(b)))
                << "polygon " << p << ": diagonal " << a << "-" << b << " on a cube face";
          }
          const Point a = doubled_vector_area({position(c[0]), position(c[1]), position(c[2])});
          for (int k = 0; k < 3; ++k) area[k] += a[k];
          triangles.polygons.push_back({c[0], c[1], c[2]});
        }
        std::vector<Point> loop;
        for (std::uint32_t i : polygon) loop.push_back(position(i));
        EXPECT_EQ(area, doubled_vector_area(loop)) << "polygon " << p;
      }
      EXPECT_EQ(face, ply.face_count());
      EXPECT_GT(diagonals, 0u);

      const test::Topology before = test::analyse(original);
      const test::Topology after = test::analyse(triangles);
      EXPECT_EQ(after.repeated_edges, 0u) << test::describe(after);
      EXPECT_EQ(after.degenerate_polygons, 0u) << test::describe(after);
      if (rule == SurfaceRule::merge_rules) {
        EXPECT_TRUE(after.closed_and_consistent()) << test::describe(after);
        EXPECT_EQ(after.euler(), before.euler());
        EXPECT_GT(after.signed_volume, 0);
      } else {
        // Table 1's holes stay exactly as they were: splitting opened or closed no edge.
        EXPECT_EQ(after.open_edges, before.open_edges) << test::describe(after);
        EXPECT_GT(after.open_edges, 0u);
      }
    }
  }
  EXPECT_EQ(configurations.size(), 256u) << "the volumes should hold every configuration";
}

}  // namespace
}  // namespace mvox
