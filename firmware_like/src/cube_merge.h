#pragma once
// The paper's phases 1 and 2 on one cube of 2x2x2 voxels, literally: an octant triangle per
// inner corner, then merges at the vertices shared by adjacent inner voxels, x pass first, then
// y, then z. The literal engine runs these steps as the slices stream in; the fast engine's case
// table (case_table.h) is these same steps run once per configuration, at compile time.
//
// State is a set of directed segments between cube-edge midpoints. Every segment lies on one
// cube face (a triangle's sides lie on the three faces through its corner), and merging keeps it
// so: that is what the rule "join the two vertices connected to it when they lie in the same
// plane" guarantees.
#include <cstdint>

#include "cube.h"
#include "mvox/assert.h"
#include "mvox/surface_method.h"
#include "mvox/mesh.h"

namespace mvox {

// The directed segments inside one cube (at most 8 triangles x 3 sides).
struct CubeSurface {
  static constexpr int kMaxSegments = 24;
  std::uint8_t segment_count = 0;
  std::uint8_t from[kMaxSegments] = {};
  std::uint8_t to[kMaxSegments] = {};
};

// The polygons of one cube: loops of cube-edge ids, each starting at its smallest edge id, loops
// ordered by that id. Each edge hosts at most one vertex, so 12 ids and 4 loops at most.
struct CubePolygons {
  static constexpr int kMaxPolygons = 4;
  std::uint8_t polygon_count = 0;
  std::uint8_t edge_count = 0;  // sum of the polygon sizes
  std::uint8_t polygon_sizes[kMaxPolygons] = {};
  std::uint8_t edges[cube::kEdges] = {};
};

constexpr void add_segment(CubeSurface& surface, int from, int to) {
  MVOX_ASSERT(surface.segment_count < CubeSurface::kMaxSegments);
  surface.from[surface.segment_count] = static_cast<std::uint8_t>(from);
  surface.to[surface.segment_count] = static_cast<std::uint8_t>(to);
  ++surface.segment_count;
}

constexpr void remove_segment(CubeSurface& surface, int index) {
  const int last = --surface.segment_count;
  surface.from[index] = surface.from[last];
  surface.to[index] = surface.to[last];
}

// PHASE 1: the triangle of the inner voxel at `corner` for the octant that points into the cube.
// Its vertices are the midpoints towards the three neighbours inside the cube. It is wound
// counter-clockwise seen from outside, that is seen from the octant's direction (sx, sy, sz):
// with m_x, m_y, m_z the midpoints, (m_y - m_x) x (m_z - m_x) = (sy*sz, sx*sz, sx*sy) / 4, which
// points along (sx, sy, sz) exactly when sx*sy*sz > 0, i.e. when an even number of the corner's
// bits are 1 (a set bit means the octant points towards negative coordinates).
constexpr void add_octant_triangle(CubeSurface& surface, int corner) {
  const int mx = cube::edge_at_corner(corner, 0);
  const int my = cube::edge_at_corner(corner, 1);
  const int mz = cube::edge_at_corner(corner, 2);
  const bool product_positive = cube::inner_count(static_cast<unsigned>(corner)) % 2 == 0;
  const int second = product_positive ? my : mz, third = product_positive ? mz : my;
  add_segment(surface, mx, second);
  add_segment(surface, second, third);
  add_segment(surface, third, mx);
}

// PHASE 2, one merge: removes the vertex on edge `e`, shared by the two inner voxels at its
// ends, and joins the vertices it was connected to. On each of the two faces through `e` exactly
// one segment enters the vertex and one leaves it (one from each voxel's polygon, wound
// oppositely as seen along the face); they are joined into one segment on that same face, the
// "same plane" of the paper's rule. When both ends are the same vertex the two polygons already
// meet there and nothing is added: that is how two quadrangles sharing their vertices cancel.
constexpr void merge_at_edge(CubeSurface& surface, int e) {
  for (int which = 0; which < 2; ++which) {
    const int face = cube::edge_face(e, which);
    int in = -1, out = -1;
    for (int i = 0; i < surface.segment_count; ++i) {
      if (surface.to[i] == e && cube::shared_face(surface.from[i], e) == face) {
        MVOX_ASSERT(in < 0);
        in = i;
      }
      if (surface.from[i] == e && cube::shared_face(e, surface.to[i]) == face) {
        MVOX_ASSERT(out < 0);
        out = i;
      }
    }
    MVOX_ASSERT((in < 0) == (out < 0));  // segments on a face enter and leave the vertex in pairs
    if (in < 0) continue;
    const int joined_from = surface.from[in], joined_to = surface.to[out];
    // Remove the later index first so the swap-removal cannot move the other one.
    remove_segment(surface, in > out ? in : out);
    remove_segment(surface, in > out ? out : in);
    if (joined_from != joined_to) add_segment(surface, joined_from, joined_to);
  }
}

// Adds the triangles of the inner corners of `config` lying on the z = `bz` face of the cube,
// then runs the x and y passes on that face: what one slice contributes to the cube.
constexpr void add_slice_of_cube(CubeSurface& surface, unsigned config, int bz) {
  for (int corner = bz << 2; corner < (bz << 2) + 4; ++corner)
    if (config >> corner & 1) add_octant_triangle(surface, corner);
  for (int axis = 0; axis < 2; ++axis) {  // x pass, then y pass
    for (int e = 4 * axis; e < 4 * axis + 4; ++e) {
      const int low = cube::edge_low_corner(e);
      if (cube::corner_bit(low, 2) != bz) continue;
      if ((config >> low & 1) && (config >> cube::edge_high_corner(e) & 1))
        merge_at_edge(surface, e);
    }
  }
}

// The z pass between the cube's two slices.
constexpr void merge_between_slices(CubeSurface& surface, unsigned config) {
  for (int e = 8; e < 12; ++e)
    if ((config >> cube::edge_low_corner(e) & 1) && (config >> cube::edge_high_corner(e) & 1))
      merge_at_edge(surface, e);
}

// Turns the merged segments into loops. After all three passes every remaining vertex lies
// between an inner and an outer corner and has one segment in and one out.
constexpr CubePolygons extract_loops(const CubeSurface& surface) {
  int next[cube::kEdges] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
  int incoming[cube::kEdges] = {};
  for (int i = 0; i < surface.segment_count; ++i) {
    MVOX_ASSERT(next[surface.from[i]] < 0);
    next[surface.from[i]] = surface.to[i];
    ++incoming[surface.to[i]];
  }
  CubePolygons polygons;
  bool visited[cube::kEdges] = {};
  for (int start = 0; start < cube::kEdges; ++start) {
    if (next[start] < 0 || visited[start]) continue;
    MVOX_ASSERT(polygons.polygon_count < CubePolygons::kMaxPolygons);
    int size = 0;
    for (int e = start; !visited[e]; e = next[e]) {
      MVOX_ASSERT(next[e] >= 0 && incoming[e] == 1);
      visited[e] = true;
      polygons.edges[polygons.edge_count + size] = static_cast<std::uint8_t>(e);
      ++size;
    }
    MVOX_ASSERT(size >= 3 && size <= kMaxPolygonVertices);
    polygons.polygon_sizes[polygons.polygon_count++] = static_cast<std::uint8_t>(size);
    polygons.edge_count = static_cast<std::uint8_t>(polygons.edge_count + size);
  }
  return polygons;
}

// The loops of `polygons` walked the other way, each still starting at its smallest edge id.
constexpr CubePolygons reversed(const CubePolygons& polygons) {
  CubePolygons result = polygons;
  int offset = 0;
  for (int p = 0; p < polygons.polygon_count; ++p) {
    const int size = polygons.polygon_sizes[p];
    for (int i = 1; i < size; ++i) result.edges[offset + i] = polygons.edges[offset + size - i];
    offset += size;
  }
  return result;
}

// The paper's Table 1 for five and six inner voxels (C5.1, C5.2 and C6.2, which the paper
// reaches through Case 3.7, Case 3.6 and its Exception Case): the cube gets the surface of the
// complementary configuration, pieces around the outer voxels, wound to face the outer side.
// It differs from the merge rules exactly where a face is ambiguous: there the merge rules keep
// the two diagonal inner voxels apart, while the complement keeps the two outer voxels apart.
constexpr bool paper_table1_applies(unsigned config) {
  const int n = cube::inner_count(config);
  if (n != 5 && n != 6) return false;
  for (int face = 0; face < cube::kFaces; ++face)
    if (cube::face_is_ambiguous(config, face)) return true;
  return false;
}

// All three passes on a whole cube, in the paper's order.
constexpr CubePolygons merge_passes(unsigned config) {
  CubeSurface surface;
  add_slice_of_cube(surface, config, 0);
  add_slice_of_cube(surface, config, 1);
  merge_between_slices(surface, config);
  return extract_loops(surface);
}

// The polygons of a cube configuration under either rule.
constexpr CubePolygons cube_polygons(unsigned config, SurfaceRule rule) {
  if (rule == SurfaceRule::paper_table1 && paper_table1_applies(config))
    return reversed(merge_passes(~config & 0xFFu));
  return merge_passes(config);
}

}  // namespace mvox
