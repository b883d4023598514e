#pragma once
// The indexed mesh the engine emits: vertices once each, polygons referring to them by index.
#include <cstdint>

namespace mvox {

// A polygon has 3 to 7 vertices (the loops a 2x2x2 cube can hold; docs/design.md section 4).
// Marching cubes emits triangles only.
constexpr int kMaxPolygonVertices = 7;

// Vertex indices travel in 32 bits. The engine numbers vertices 0, 1, 2, ... without limit (a
// 10^12-voxel scan can pass four billion) and a polygon carries each of its indices modulo 2^32.
// That loses nothing: a polygon only refers to vertices of its own layer of cubes, fewer than
// kMaxVerticesBack emitted before the polygon (the engine refuses slices large enough to break
// that), so a sink that counts the vertices it has taken finds each whole index with
// whole_vertex_index(). Below 2^32 vertices the two are the same number.
constexpr std::uint64_t kMaxVerticesBack = std::uint64_t{1} << 32;

// The whole index of the vertex a polygon gives as `index` (modulo 2^32), for a sink that has
// taken `vertices_taken` vertices (at least one) when the polygon arrives: the one index
// congruent to it among the last 2^32 taken. An index beyond what was taken comes out at or
// above `vertices_taken`, so a sink can still tell it is bad.
constexpr std::uint64_t whole_vertex_index(std::uint32_t index, std::uint64_t vertices_taken) {
  return vertices_taken - 1 -
         static_cast<std::uint32_t>(static_cast<std::uint32_t>(vertices_taken - 1) - index);
}

// Axis of the voxel pair a vertex sits between: x, y or z neighbours.
enum class Axis : std::uint8_t { x = 0, y = 1, z = 2 };

// A surface vertex at the midpoint of an inner voxel and an outer 6-adjacent voxel (marching
// voxels), or elsewhere on the segment between them (marching cubes interpolates).
// Coordinates are in voxel units: x = column, y = row, z = slice index, so the midpoint of
// voxels (3,4,5) and (4,4,5) is (3.5, 4, 5). The engine numbers vertices 0, 1, 2, ... in the
// order they are emitted. `inner_is_lower` tells whether the inner voxel is the one with the
// smaller coordinate along `axis`; with it a sink can find the outward direction.
struct Vertex {
  float x = 0, y = 0, z = 0;
  Axis axis = Axis::x;
  bool inner_is_lower = false;
};

// The coordinate of `vertex` along its voxel pair's axis: the one that interpolation and
// smoothing move (the other two are the pair's own, whole numbers).
constexpr float& along_axis(Vertex& vertex) {
  return vertex.axis == Axis::x ? vertex.x : vertex.axis == Axis::y ? vertex.y : vertex.z;
}
constexpr float along_axis(const Vertex& vertex) {
  return vertex.axis == Axis::x ? vertex.x : vertex.axis == Axis::y ? vertex.y : vertex.z;
}

// Vertex indices wound counter-clockwise seen from outside (outward normal by the right-hand
// rule, from inner to outer). Every index was emitted in a vertex batch before this polygon.
struct Polygon {
  std::uint8_t vertex_count = 0;
  std::uint32_t vertices[kMaxPolygonVertices] = {};
};

// The same polygon with its vertices by value, in the same order: for sinks that draw rather
// than index (the renderer), so that they need not keep every vertex of the last layers.
struct PolygonGeometry {
  std::uint8_t vertex_count = 0;
  Vertex vertices[kMaxPolygonVertices] = {};
};

}  // namespace mvox
